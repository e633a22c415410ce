// Statistics of a volume's voxels inside a flat ROI, in world space (docs/viewer.md,
// "Measurements"): exact for any placement of the grid, oblique and tilted ones too.
//
// The rule: a voxel is inside when the ROI's plane passes through its box (its centre lies within
// half the box's extent along the plane's normal, the lower bound closed and the upper open, so
// that a plane between two layers of voxels takes one of them) and its centre, projected along
// the normal onto the plane, lies inside the region. On a plane through voxel centres parallel to
// a layer of the grid, these are the voxels of that layer whose centres are inside: what the 2-D
// view shows under the ROI.
#pragma once
#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "intermix/scene.hpp"
#include "measure/planar_region.hpp"
#include "scene/annotation.hpp"

namespace imx {

struct RoiStatistics {
  size_t voxels = 0;      // inside the ROI, finite values only
  size_t non_finite = 0;  // inside, NaN or infinite: not in the statistics
  // Over the finite values, in the volume's units; NaN when there are none. sd is the
  // population's (divided by the count), as a reading of all the region's voxels.
  double mean = 0.0, sd = 0.0, min = 0.0, max = 0.0;
};

// The voxels of `volume` inside `region` (by the rule above), as [i, j, k] indices in k, j, i
// order, for tests and tools.
std::vector<glm::ivec3> roi_voxels(const VolumeObject& volume, const PlanarRegion& region);

// Their statistics; the work is bounded by the voxels the plane passes through in the region's
// box.
RoiStatistics roi_statistics(const VolumeObject& volume, const PlanarRegion& region);

}  // namespace imx
