// Where a figure's volumes lie in the patient: the anatomy's box above its background, where an
// overlay shows, and an overlay's peak. Bounded work on any volume: a strided scan.
#pragma once
#include <functional>
#include <optional>

#include <glm/vec3.hpp>

#include "intermix/scene.hpp"
#include "scene/camera_framing.hpp"  // WorldBox

namespace imx {

inline glm::dvec3 box_centre(const WorldBox& box) {
  return 0.5 * (box.lo + box.hi);
}
inline glm::dvec3 box_size(const WorldBox& box) {
  return box.hi - box.lo;
}

// The box (LPS mm) of the voxel cells whose finite value passes `keep`, from a scan of at most
// about 16 M voxels (every s-th along each axis, the box widened by s voxels); nullopt when no
// scanned voxel passes.
std::optional<WorldBox> voxel_box(const VolumeObject& volume,
                                  const std::function<bool(double)>& keep);

// The value above which an anatomy's voxels are the subject, not the background: its 2nd
// percentile plus a tenth of its robust range (2nd to 98th percentile), above air on CT and the
// zeros around an MR head; nullopt for a volume of one value.
std::optional<double> background_level(const VolumeObject& anatomy);

// The box of the grid's voxel cells, whole.
WorldBox grid_box(const VolumeObject& volume);

// The anatomy's box: its voxels above background_level; the whole grid when none is.
WorldBox anatomy_box(const VolumeObject& anatomy);

// The centre (LPS mm) of a voxel of largest finite magnitude (the first in memory order among
// equals); the grid's centre when no voxel is finite.
glm::dvec3 peak_point(const VolumeObject& volume);

}  // namespace imx
