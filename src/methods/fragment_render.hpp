// Orchestration shared by every method that works per sample ray: tiles in parallel, each
// sample's fragments in the order the method's store pass sees them (depth or arrival), a
// per-tile kernel object holding the tile's scratch buffers, a box filter per pixel.
#pragma once
#include <span>
#include <vector>

#include "core/colour.hpp"
#include "core/parallel.hpp"
#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "methods/frame_setup.hpp"
#include "methods/sample_pattern.hpp"
#include "raster/rasterizer.hpp"

namespace imx {

// `make_kernel()` is called once per tile; the object it returns is called as
// `kernel(const Ray&, std::span<Fragment>, VolumeMask)` (the sample's fragments, which it may
// reorder, and the volumes that may show in its pixel) and returns the premultiplied colour of
// one sample ray.
template <class MakeKernel>
Image render_fragment_method(const Scene& scene, const FrameSetup& frame, int spp,
                             const RenderOptions& options, FragmentOrder order,
                             const MakeKernel& make_kernel) {
  constexpr int kTileSize = 16;
  std::vector<glm::vec2> offsets = stratified_offsets(spp);
  Rasterizer raster(scene, frame.camera, frame.volumes, kTileSize);
  const int w = scene.image.width, h = scene.image.height;
  Image image(w, h);
  const glm::vec4 background = scene.image.background;
  const float weight = 1.0f / static_cast<float>(offsets.size());
  for_each_tile(
      w, h, kTileSize, options.threads,
      [&](const TileRect& tile, int) {
        auto kernel = make_kernel();
        SampleFragments fragments;
        raster.rasterize(tile, offsets, fragments, order);
        size_t sample = 0;
        for (int y = tile.y0; y < tile.y1; ++y)
          for (int x = tile.x0; x < tile.x1; ++x) {
            glm::vec4 sum(0.0f);
            const VolumeMask may_show = frame.volumes_may_show(x, y);
            for (const glm::vec2& o : offsets) {
              std::span<Fragment> row(fragments.fragments.data() + fragments.offsets[sample],
                                      fragments.offsets[sample + 1] - fragments.offsets[sample]);
              ++sample;
              sum += kernel(frame.camera.ray(x + o.x, y + o.y), row, may_show);
            }
            image.at(x, y) = over_background(sum * weight, background);
          }
      },
      [&](int done, int total) {
        if (options.progress) options.progress(static_cast<double>(done) / total);
      });
  return image;
}

}  // namespace imx
