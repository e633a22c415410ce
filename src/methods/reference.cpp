#include "methods/reference.hpp"

#include <fmt/format.h>

#include "core/colour.hpp"
#include "core/parallel.hpp"
#include "intermix/error.hpp"
#include "methods/frame_setup.hpp"
#include "methods/reference_kernel.hpp"
#include "methods/sample_pattern.hpp"
#include "raster/rasterizer.hpp"

namespace imx {

namespace {
constexpr int kTileSize = 16;
}

Image render_reference(const Scene& scene, int spp, const RenderOptions& options) {
  FrameSetup frame(scene);
  if (frame.volumes.size() > static_cast<size_t>(kMaxReferenceVolumes))
    throw Error(fmt::format("reference: the scene has {} volumes, at most {} are supported",
                            frame.volumes.size(), kMaxReferenceVolumes));
  for (const PreparedVolume& v : frame.volumes)
    if (v.object->style == VolumeStyle::mip || v.object->style == VolumeStyle::xray)
      throw Error(fmt::format("volume '{}': style mip/xray is not available in the reference yet",
                              v.object->name));
  ReferenceParams params;
  double step = scene.render.step_mm > 0.0 ? scene.render.step_mm
                                           : frame.min_pitch * scene.render.reference_step_fraction;
  params.step = step;
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
            for (const glm::vec2& o : offsets) {
              Ray ray = frame.camera.ray(x + o.x, y + o.y);
              sum +=
                  trace_reference(ray, fragments.of(sample++), frame.volumes, frame.lights, params);
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
