// TrackVis's point space: points are in "voxmm" (voxel index times voxel size, the origin at the
// first voxel's corner, axes in the header's voxel order), mapped to RAS+ mm exactly as nibabel's
// get_affine_trackvis_to_rasmm does (nibabel 5.0, streamlines/trk.py).
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include <glm/mat4x4.hpp>

namespace imx::detail {

struct TrkSpace {
  std::array<int16_t, 3> dims{};
  std::array<float, 3> voxel_sizes{};
  std::array<std::array<float, 4>, 4> vox_to_ras{};  // row by row, as stored; already recorded
  std::string voxel_order;                           // as nibabel gives it: trailing NULs removed
};

// voxmm -> RAS+ mm: divide by the voxel sizes, shift by half a voxel (TrackVis counts from the
// voxel's corner, nibabel from its centre), reorder and flip the axes from the header's voxel order
// to the order vox_to_ras implies, then vox_to_ras; rounded to float32 as nibabel does. Throws
// imx::Error naming `what` and the field: a voxel order that is not three distinct axis letters
// (L/R, P/A, I/S), a singular or non-finite vox_to_ras, a zero or non-finite voxel size.
glm::dmat4 trk_voxmm_to_ras(const TrkSpace& space, const std::string& what);

}  // namespace imx::detail
