// Orchestration shared by methods that trace each sample ray independently: tiles in parallel,
// rasterized fragments per sample, a pure kernel per ray, a box filter per pixel.
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

// `kernel(const Ray&, std::span<const Fragment>)` returns the premultiplied colour of one ray.
template <class Kernel>
Image render_per_sample(const Scene& scene, const FrameSetup& frame, int spp,
                        const RenderOptions& options, const Kernel& kernel) {
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
        SampleFragments fragments;
        raster.rasterize(tile, offsets, fragments);
        size_t sample = 0;
        for (int y = tile.y0; y < tile.y1; ++y)
          for (int x = tile.x0; x < tile.x1; ++x) {
            glm::vec4 sum(0.0f);
            for (const glm::vec2& o : offsets)
              sum += kernel(frame.camera.ray(x + o.x, y + o.y), fragments.of(sample++));
            image.at(x, y) = over_background(sum * weight, background);
          }
      },
      [&](int done, int total) {
        if (options.progress) options.progress(static_cast<double>(done) / total);
      });
  return image;
}

}  // namespace imx
