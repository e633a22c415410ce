// One frame's voxels from a file that stores its frames one after another (4-D NIfTI and
// Analyze, MGH): the check that all frames' data is there, and the read of one frame's box.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include "intermix/volume.hpp"
#include "io/voxels/raw_voxels.hpp"

namespace imx::detail {

// The most frames a file may declare. NIfTI-1 cannot count past 32767; larger counts (NIfTI-2's
// 64-bit dims, MGH's int32) are corrupt headers, and each frame gets a label in memory.
inline constexpr int64_t kMaxFrames = int64_t{1} << 16;

// Where a file's voxels are: `frames` grids of `dims` elements of `type`, x fastest, frame after
// frame, `offset` bytes into `file` (counted in inflated bytes when it is gzip data).
struct FrameLayout {
  std::filesystem::path file;  // the file holding the voxels
  std::string what;            // names them in messages: "x.img (voxel data of x.hdr)"
  bool gzipped = false;
  uint64_t offset = 0;
  RawType type = RawType::u8;
  bool swap = false;  // the file's byte order is not the host's
  glm::ivec3 dims{0};
  int frames = 1;

  uint64_t frame_bytes() const;
  uint64_t total_bytes() const;  // all frames
};

// Throws imx::Error naming `what` unless 1 <= frames <= kMaxFrames and frames of `dims` can be
// indexed as one grid of dims.z * frames slices (what read_frame_voxels reads them as). `dims`
// must be positive, with no more than kMaxVoxels voxels (the header parsers check that first).
void check_frame_count(glm::ivec3 dims, int64_t frames, const std::string& what);

// The voxels of `box` (inside dims) of frame `frame` (0 <= frame < frames), converted and
// byte-swapped as load_voxels does, holding no more than the box in memory. The file must hold
// every frame's data, so that a truncated series is refused whichever frame is asked for:
// uncompressed data is checked by the file's size and read run by run with seeks; gzip data is
// inflated from the start to its end, keeping only the box, so that its checksum is checked.
// Throws imx::Error naming layout.what.
VoxelStorage read_frame_voxels(const FrameLayout& layout, int frame, const VoxelBox& box);

}  // namespace imx::detail
