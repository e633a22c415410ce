// Frames of multi-frame (4-D) files: the check every reader makes of the frame it is asked for,
// and the volume every reader's whole and region reads assemble.
#pragma once
#include <string>
#include <utility>

#include "intermix/volume.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

// Throws imx::Error naming `what` unless 0 <= frame < frames.
void require_frame(int frame, int frames, const std::string& what);

// The voxels of `box` of frame `frame` of a grid of `frames` frames placed as `header` says:
// the frame and the box are checked, `read(box)` gives the voxels (a VoxelStorage), and the
// volume is placed where the box lies and validated.
template <class Read>
VolumeData frame_box_volume(const VolumeHeader& header, int frames, int frame, const VoxelBox& box,
                            const std::string& what, Read&& read) {
  require_frame(frame, frames, what);
  require_box_inside(header.dims, box, what);
  VolumeData v;
  v.dims = box.size();
  v.index_to_world = box_index_to_world(header.index_to_world, box.lo);
  v.voxels = std::forward<Read>(read)(box);
  v.validate(what);
  return v;
}

}  // namespace imx::detail
