#include "dist/bricked_render.hpp"

#include <algorithm>
#include <cmath>

#include "core/parallel.hpp"
#include "dist/partition.hpp"
#include "dist/rank_scene.hpp"
#include "dist/slab_message.hpp"
#include "intermix/limits.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "methods/cancellable.hpp"
#include "methods/zslab/zslab.hpp"
#include "volume/level_of_detail.hpp"

namespace imx {

int bricks_needed(const Scene& outline) {
  const double most_voxels = static_cast<double>(detail::kMaxVoxels) / 4;
  const double most_bytes = static_cast<double>(input_limits().max_memory) / 4;
  double parts = 1.0;
  for (const VolumeObject& v : outline.volumes) {
    const double voxels = static_cast<double>(v.source_dims.x) * v.source_dims.y * v.source_dims.z;
    const double bytes =
        voxels * static_cast<double>(
                     std::visit([](const auto& b) { return sizeof(*b.data()); }, v.data->voxels));
    parts = std::max({parts, voxels / most_voxels, bytes / most_bytes});
  }
  // Aprons and uneven halving make bricks up to a few percent larger than an even share.
  return static_cast<int>(std::ceil(parts * 1.05));
}

namespace {

// Brick k's document and regions: each pyramid volume's source at the level `levels` picks for
// the brick, read over the level's voxels that cover the brick.
struct BrickSource {
  nlohmann::json json;
  VolumeRegionChooser regions;
  int coarsest_level = 0;
};

BrickSource brick_source(const SceneDocument& outline, const Partition& partition, int k,
                         const std::vector<PyramidLevels>& pyramids, const BrickLevelRule& levels) {
  const Scene& scene = outline.scene();
  BrickSource out{outline.json(), rank_regions(partition, k, scene), 0};
  if (!levels) return out;
  std::map<std::string, VoxelBox> coarse;  // object name -> its box at the chosen level
  for (const PyramidLevels& p : pyramids) {
    const VolumeObject& v = scene.volumes[static_cast<size_t>(scene.order[p.object].index)];
    const auto brick = partition.ranks[static_cast<size_t>(k)].bricks.find(v.name);
    if (brick == partition.ranks[static_cast<size_t>(k)].bricks.end()) continue;
    glm::dvec3 lo, hi;
    world_bounds(p, brick->second.read, lo, hi);
    const int fitting = level_fitting(p, pixel_footprint(scene.camera, scene.image.height, lo, hi));
    const int level = std::clamp(levels(p.object, fitting), 0, static_cast<int>(p.dims.size()) - 1);
    if (level == 0) continue;
    nlohmann::json& src = out.json["objects"][p.object]["source"];
    if (!src.is_object()) src = nlohmann::json{{"file", src}};
    src["level"] = p.first_level + level;
    coarse.emplace(v.name, box_at_level(p, level, brick->second.read));
    out.coarsest_level = std::max(out.coarsest_level, level);
  }
  if (!coarse.empty())
    out.regions = [coarse, fine = out.regions](const std::string& object,
                                               const VolumeHeader& header) {
      const auto it = coarse.find(object);
      return it != coarse.end() ? it->second : fine(object, header);
    };
  return out;
}

}  // namespace

BrickedFrame render_in_bricks(const SceneDocument& outline, int bricks,
                              const RenderOptions& options, const BrickLevelRule& levels) {
  const Scene& scene = outline.scene();
  const Partition partition = plan_partition(scene, bricks, PartitionMode::bricks);
  const std::vector<PyramidLevels> pyramids =
      levels ? scene_pyramids(outline) : std::vector<PyramidLevels>{};
  int coarsest_level = 0;
  const int spp = options.spp > 0 ? options.spp : std::max(scene.render.spp, 1);
  const int threads = resolve_thread_count(options.threads);
  const size_t pixels = static_cast<size_t>(scene.image.width) * scene.image.height;
  const PixelRange all{0, pixels};
  const IntermixSettings mix = zslab_params(scene.render).mix;
  ZtBuffer frame;
  for (int k = 0; k < bricks; ++k) {
    RenderOptions part_options = options;
    if (options.progress)
      part_options.progress = [&, k](double f) { options.progress((k + f) / bricks); };
    part_options = cancellable(part_options);  // throws Cancelled between bricks, and in them
    ZtBuffer arrays;
    {
      // The part's voxels live only while it renders.
      BrickSource source = brick_source(outline, partition, k, pyramids, levels);
      coarsest_level = std::max(coarsest_level, source.coarsest_level);
      const SceneDocument part(std::move(source.json), outline.origin(), outline.base_dir(), {}, {},
                               std::move(source.regions));
      render_zslab_arrays(rank_scene(part.scene(), partition, k), spp, part_options, arrays);
    }
    if (k == 0)
      frame = std::move(arrays);
    else
      merge_slab_message(frame, all, spp, encode_slab_message(arrays, all, spp, threads), true, mix,
                         threads);
  }
  const std::vector<glm::vec4> rgba =
      resolve_slab_arrays(frame, all, spp, mix.a_ert, scene.image.background, threads);
  BrickedFrame out{Image(scene.image.width, scene.image.height), coarsest_level};
  for (size_t p = 0; p < pixels; ++p)
    out.image.at(static_cast<int>(p % scene.image.width), static_cast<int>(p / scene.image.width)) =
        rgba[p];
  return out;
}

}  // namespace imx
