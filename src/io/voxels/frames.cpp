#include "io/voxels/frames.hpp"

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx::detail {

void require_frame(int frame, int frames, const std::string& what) {
  if (frame >= 0 && frame < frames) return;
  throw Error(frames == 1
                  ? fmt::format("{}: frame {} asked for, but it holds one frame (0)", what, frame)
                  : fmt::format("{}: frame {} asked for, but it holds {} frames (0 to {})", what,
                                frame, frames, frames - 1));
}

}  // namespace imx::detail
