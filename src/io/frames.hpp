// Frames of multi-frame (4-D) files: the check every reader makes of the frame it is asked for.
#pragma once
#include <string>

namespace imx::detail {

// Throws imx::Error naming `what` unless 0 <= frame < frames.
void require_frame(int frame, int frames, const std::string& what);

}  // namespace imx::detail
