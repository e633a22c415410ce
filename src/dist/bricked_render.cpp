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

Image render_in_bricks(const SceneDocument& outline, int bricks, const RenderOptions& options) {
  const Scene& scene = outline.scene();
  const Partition partition = plan_partition(scene, bricks, PartitionMode::bricks);
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
      const SceneDocument part(outline.json(), outline.origin(), outline.base_dir(), {}, {},
                               rank_regions(partition, k, scene));
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
  Image image(scene.image.width, scene.image.height);
  for (size_t p = 0; p < pixels; ++p)
    image.at(static_cast<int>(p % scene.image.width), static_cast<int>(p / scene.image.width)) =
        rgba[p];
  return image;
}

}  // namespace imx
