// Checks shared by VolumeData::validate, crop and the readers that read a box or a header only.
#pragma once
#include <string>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "intermix/volume.hpp"

namespace imx::detail {

// Throws imx::Error naming `what` unless `box` is non-empty and inside a grid of `dims`.
void require_box_inside(glm::ivec3 dims, const VoxelBox& box, const std::string& what);

// Throws imx::Error naming `what` unless `index_to_world` is finite and invertible, with voxel
// spacings and an origin within the renderer's limits: validate's placement checks, for a
// header read without its voxels.
void check_placement(const glm::dmat4& index_to_world, const std::string& what);

}  // namespace imx::detail
