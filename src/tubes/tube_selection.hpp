// Which streamlines of a streamline object are drawn: its stride, minimum length and regions.
#pragma once
#include <cstdint>
#include <vector>

#include "intermix/scene.hpp"

namespace imx {

// Indices of the streamlines `object` draws, ascending: every stride-th one at least
// min_length mm long (summed segment lengths), with at least two points, that passes through
// every "through" region and touches no "avoid" region (a point inside counts). Uses both cores.
std::vector<uint32_t> select_streamlines(const StreamlineObject& object);

// Whether world point `p` lies inside `region` (its sphere, its label's voxels by nearest voxel,
// or its closed mesh by ray parity).
bool inside_region(const StreamlineRegion& region, const glm::vec3& p);

}  // namespace imx
