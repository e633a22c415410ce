#include "io/voxels/frame_voxels.hpp"

#include <cerrno>
#include <climits>
#include <fstream>
#include <system_error>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/inflate_charge.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"
#include "io/voxels/mapped_voxels.hpp"

namespace imx::detail {

uint64_t FrameLayout::frame_bytes() const {
  return static_cast<uint64_t>(dims.x) * static_cast<uint64_t>(dims.y) *
         static_cast<uint64_t>(dims.z) * raw_type_size(type);
}

uint64_t FrameLayout::total_bytes() const {
  return frame_bytes() * static_cast<uint64_t>(frames);
}

void check_frame_count(glm::ivec3 dims, int64_t frames, const std::string& what) {
  if (frames < 1 || frames > kMaxFrames)
    throw Error(fmt::format("{}: {} frames; a file may hold 1 to {}", what, frames, kMaxFrames));
  if (static_cast<int64_t>(dims.z) * frames > INT_MAX)
    throw Error(fmt::format("{}: {} frames of {} slices are more slices than {} in all", what,
                            frames, dims.z, INT_MAX));
}

VoxelStorage read_frame_voxels(const FrameLayout& l, int frame, const VoxelBox& box) {
  // Frames follow each other with x fastest, so the series is one grid of dims.z * frames
  // slices, and frame k's box is the box moved by k * dims.z slices: the region readers' seeks
  // and streaming skips then serve any frame, and the gzip path's check of the whole stream
  // (its length and its checksum) covers every frame.
  const glm::ivec3 stacked(l.dims.x, l.dims.y, l.dims.z * l.frames);
  const glm::ivec3 shift(0, 0, l.dims.z * frame);
  const VoxelBox moved{box.lo + shift, box.hi + shift};
  const uint64_t needed = l.total_bytes();
  const std::string of_frames =
      l.frames > 1 ? fmt::format(" ({} frames of {})", l.frames, l.frame_bytes()) : "";

  require_regular_file(l.file, l.what);
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(l.file, ec);
  if (ec) throw Error(fmt::format("{}: cannot read its size: {}", l.what, ec.message()));
  if (l.gzipped) {
    check_inflatable(static_cast<size_t>(l.offset + needed), static_cast<size_t>(size), l.what);
    // Before the box's own limits: compressed data has no bricks to fall back on.
    refuse_compressed_claim(l.frame_bytes(), VoxelBox::whole(l.dims).count() > kMaxVoxels, l.what,
                            l.frames > 1 ? "gzip voxel data of one frame" : "gzip voxel data");
  } else if (size < l.offset + needed) {
    const uintmax_t found = size > l.offset ? size - l.offset : 0;
    throw Error(fmt::format("{}: expected {} bytes of voxel data{}, found {}", l.what, needed,
                            of_frames, found));
  }
  require_loadable_box(box, l.what);
  // A whole frame of native, uncompressed voxels: viewed in place.
  if (!l.gzipped && !l.swap && box == VoxelBox::whole(l.dims))
    if (auto mapped = map_voxels(l.file, l.offset + static_cast<uint64_t>(frame) * l.frame_bytes(),
                                 l.type, box.count()))
      return std::move(*mapped);
  std::ifstream in = open_input_stream(l.file, l.what);
  if (l.gzipped)
    return load_gzip_voxels(in, static_cast<size_t>(l.offset), l.type, stacked, moved, l.swap,
                            l.what);
  return load_raw_voxels(in, l.offset, l.type, stacked, moved, l.swap, l.what);
}

}  // namespace imx::detail
