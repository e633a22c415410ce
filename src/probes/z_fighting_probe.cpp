#include "probes/z_fighting_probe.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/parallel.hpp"
#include "frame/frame_setup.hpp"
#include "intermix/error.hpp"
#include "raster/rasterizer.hpp"

namespace imx {

std::vector<uint8_t> coplanar_region(const Scene& scene, float relative_tolerance) {
  constexpr int kTile = 16;
  FrameSetup frame(scene);
  Rasterizer raster(scene, frame.camera, frame.volumes, kTile);
  const int w = scene.image.width, h = scene.image.height;
  std::vector<uint8_t> hit(size_t(w) * h, 0);
  const glm::vec2 centre(0.5f);
  for_each_tile(w, h, kTile, 0, [&](const TileRect& tile, int) {
    SampleFragments f;
    raster.rasterize(tile, {&centre, 1}, f);
    size_t s = 0;
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        std::span<const Fragment> row = f.of(s++);
        for (size_t i = 1; i < row.size(); ++i)
          if (row[i].object != row[i - 1].object &&
              row[i].t - row[i - 1].t <= relative_tolerance * row[i].t)
            hit[size_t(y) * w + x] = 1;
      }
  });
  std::vector<uint8_t> region(hit.size(), 0);
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      bool all = true;
      for (int j = -1; j <= 1 && all; ++j)
        for (int i = -1; i <= 1 && all; ++i) all = hit[size_t(y + j) * w + (x + i)] != 0;
      region[size_t(y) * w + x] = all ? 1 : 0;
    }
  return region;
}

Camera shifted_camera(const Scene& scene, glm::dvec2 pixels) {
  CameraModel model(scene.camera, scene.image.width, scene.image.height);
  double footprint = model.pixel_footprint(glm::length(scene.camera.target - scene.camera.eye));
  // moving the camera right moves the image left: shift the camera the opposite way
  glm::dvec3 shift = (-pixels.x * model.right() + pixels.y * model.up()) * footprint;
  Camera c = scene.camera;
  c.eye += shift;
  c.target += shift;
  return c;
}

ZFightingStats measure_z_fighting(const Scene& scene, const RenderOptions& options,
                                  glm::dvec2 jitter_pixels) {
  std::vector<uint8_t> region = coplanar_region(scene);
  bool any = false;
  for (uint8_t r : region) any = any || r;
  if (!any)
    throw Error(fmt::format("z-fighting: no coplanar surfaces are seen at {}x{}", scene.image.width,
                            scene.image.height));
  Image image = render(scene, options);
  Scene shifted = scene;
  shifted.camera = shifted_camera(scene, jitter_pixels);
  Image jittered = render(shifted, options);
  return z_fighting(image, jittered, region);
}

}  // namespace imx
