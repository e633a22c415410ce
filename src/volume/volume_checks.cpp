#include "volume/volume_checks.hpp"

#include <cmath>

#include <fmt/format.h>
#include <glm/mat3x3.hpp>

#include "core/limits.hpp"
#include "core/math.hpp"
#include "intermix/error.hpp"

namespace imx::detail {

void require_box_inside(glm::ivec3 dims, const VoxelBox& box, const std::string& what) {
  for (int a = 0; a < 3; ++a)
    if (box.lo[a] < 0 || box.hi[a] > dims[a] || box.hi[a] <= box.lo[a])
      throw Error(fmt::format(
          "{}: voxel box [{}, {}) x [{}, {}) x [{}, {}) is empty or leaves the {}x{}x{} grid", what,
          box.lo.x, box.hi.x, box.lo.y, box.hi.y, box.lo.z, box.hi.z, dims.x, dims.y, dims.z));
}

void check_placement(const glm::dmat4& index_to_world, const std::string& what) {
  if (!all_finite(index_to_world))
    throw Error(fmt::format("{}: the index-to-world transform has a non-finite entry", what));
  if (std::abs(glm::determinant(glm::dmat3(index_to_world))) < 1e-12)
    throw Error(fmt::format("{}: the index-to-world transform is singular", what));
  for (int axis = 0; axis < 3; ++axis) {
    const double pitch = glm::length(glm::dvec3(index_to_world[axis]));
    if (pitch < kMinLengthMm || pitch > kMaxLengthMm)
      throw Error(fmt::format("{}: voxel spacing {:g} mm along axis {} is outside {:g} to {:g} mm",
                              what, pitch, axis, kMinLengthMm, kMaxLengthMm));
    if (std::abs(index_to_world[3][axis]) > kMaxCoordinateMm)
      throw Error(fmt::format("{}: origin {:g} mm along axis {} is more than {:g} mm from 0", what,
                              index_to_world[3][axis], axis, kMaxCoordinateMm));
  }
}

}  // namespace imx::detail
