// Levels of detail: how large a pixel is where a volume lies, and coarser copies of a volume
// for frames whose pixels are larger than its voxels (a pyramid's next level, built in memory).
#pragma once
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "intermix/scene.hpp"
#include "intermix/volume.hpp"

namespace imx {

// The world size (mm) of one pixel of `camera` over an image `image_height` pixels high, at the
// nearest point to the eye of the world box `lo`..`hi` (0 when the eye is level with or past it).
double pixel_footprint(const Camera& camera, int image_height, const glm::dvec3& lo,
                       const glm::dvec3& hi);

// The longest edge (mm) of a voxel placed by `index_to_world`.
double longest_voxel_edge(const glm::dmat4& index_to_world);

// The world box of the voxel centres `lo`..`hi` - 1 (half-open indices) placed by
// `index_to_world`.
void world_box(const glm::dmat4& index_to_world, glm::ivec3 lo, glm::ivec3 hi, glm::dvec3& box_lo,
               glm::dvec3& box_hi);

// The next level of `data`: means of 2x2x2 voxels (the last of an odd axis repeated; integers
// rounded half away from zero), voxel i centred on data's index 2i + 0.5, as `intermix convert`
// writes a pyramid. Scalar volumes only (a colour volume throws imx::Error).
VolumeData halved(const VolumeData& data);

}  // namespace imx
