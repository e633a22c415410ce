#include "server/moving_levels.hpp"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "volume/level_of_detail.hpp"

namespace imx::server {

std::shared_ptr<const VolumeData> MovingLevels::level_of(
    const std::shared_ptr<const VolumeData>& base, int level) {
  // Levels of volumes no longer shown (an edited source, another 4-D frame) are let go.
  std::erase_if(cache_, [](const Levels& l) { return l.base.expired(); });
  auto it = std::find_if(cache_.begin(), cache_.end(),
                         [&](const Levels& l) { return l.base.lock() == base; });
  if (it == cache_.end()) it = cache_.insert(cache_.end(), Levels{base, {}});
  while (static_cast<int>(it->coarser.size()) < level) {
    const VolumeData& finer = it->coarser.empty() ? *base : *it->coarser.back();
    it->coarser.push_back(std::make_shared<const VolumeData>(halved(finer)));
  }
  return it->coarser[static_cast<size_t>(level - 1)];
}

int MovingLevels::apply(Scene& scene) {
  int coarsest = 0;
  for (VolumeObject& v : scene.volumes) {
    if (!v.data || v.data->colours || v.labels || v.data->voxel_count() < kMovingLevelVoxels)
      continue;
    const glm::ivec3 dims = v.data->dims;
    if (!v.region.empty() && v.region != VoxelBox::whole(dims)) continue;  // a part of a source
    glm::dvec3 lo, hi;
    world_box(v.index_to_world, glm::ivec3(0), dims, lo, hi);
    const double footprint = pixel_footprint(scene.camera, scene.image.height, lo, hi);
    const double edge = longest_voxel_edge(v.index_to_world);
    int level = 0;
    // Each level doubles the voxel's edges; the smallest axis keeps at least two voxels.
    while (edge * std::ldexp(1.0, level + 1) <= footprint &&
           std::min({dims.x, dims.y, dims.z}) >> (level + 1) >= 2)
      ++level;
    if (level == 0) continue;
    const std::shared_ptr<const VolumeData> coarse = level_of(v.data, level);
    // The object's own transform, applied to the level's placement.
    v.index_to_world =
        v.index_to_world * glm::inverse(v.data->index_to_world) * coarse->index_to_world;
    v.data = coarse;
    v.source_dims = coarse->dims;
    if (!v.region.empty()) v.region = VoxelBox::whole(coarse->dims);
    coarsest = std::max(coarsest, level);
  }
  return coarsest;
}

}  // namespace imx::server
