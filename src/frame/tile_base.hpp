// The tile base (render_fragment_method): the orchestration shared by every method that works
// per sample ray (the fragment family and csg directly, reference and mdvr through the ray base,
// ray_base.hpp): tiles in parallel, each sample's fragments in the order the method's store pass
// sees them (depth or arrival), the clip step of each sample ray in a scene with clip geometry, a
// per-tile kernel object holding the tile's scratch buffers, a box filter per pixel.
#pragma once
#include <optional>
#include <span>
#include <type_traits>
#include <vector>

#include "core/colour.hpp"
#include "core/parallel.hpp"
#include "frame/clip_intervals.hpp"
#include "frame/frame_setup.hpp"
#include "frame/sample_pattern.hpp"
#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "raster/rasterizer.hpp"
#include "tubes/tube_coverage.hpp"
#include "volume/wide_scalar.hpp"

namespace imx {

// `make_kernel()` is called once per tile; the object it returns is called as
// `kernel(const Ray&, std::span<Fragment>, const VolumeFilter&)` (the sample's fragments, which
// it may reorder, and which volumes may show in its pixel and what the ray keeps of the clipped
// ones) and returns the premultiplied colour of one sample ray. A kernel that takes a VolumeMask
// instead gets only the mask, and with it no clipping (render() refuses clip geometry where such
// a kernel would see it).
template <class MakeKernel>
Image render_fragment_method(const Scene& scene, const FrameSetup& frame, int spp,
                             const RenderOptions& options, FragmentOrder order,
                             const MakeKernel& make_kernel) {
  constexpr int kTileSize = 16;
  std::vector<glm::vec2> offsets = frame_offsets(spp, options.sample_index);
  Rasterizer raster(scene, frame.camera, frame.volumes, kTileSize, RasterObjects::shown,
                    tube_coverage_on(scene.render, false));
  // The clip meshes' fragments come in rows of their own, sorted by depth whatever `order` is:
  // cutters that do not show never reach the method's fragments, and no store pass sees them.
  std::optional<Rasterizer> clip_raster;
  if (!frame.clip.empty())
    clip_raster.emplace(scene, frame.camera, frame.volumes, kTileSize, RasterObjects::clip);
  const ClipView clip_view = frame.clip.view();
  const int w = scene.image.width, h = scene.image.height;
  Image image(w, h);
  const glm::vec4 background = scene.image.background;
  const float weight = 1.0f / static_cast<float>(offsets.size());
  const bool wide = wide_scalar_available();  // the kernel runs its x86-64-v3 copy
  for_each_tile(
      w, h, kTileSize, options.threads,
      [&](const TileRect& tile, int) {
        auto kernel = make_kernel();
        SampleFragments fragments, clip_fragments;
        raster.rasterize(tile, offsets, fragments, order);
        if (clip_raster) clip_raster->rasterize(tile, offsets, clip_fragments);
        RayClip clip;
        size_t sample = 0;
        for (int y = tile.y0; y < tile.y1; ++y)
          for (int x = tile.x0; x < tile.x1; ++x) {
            glm::vec4 sum(0.0f);
            VolumeFilter filter(frame.volumes_may_show(x, y));
            for (const glm::vec2& o : offsets) {
              std::span<Fragment> row(fragments.fragments.data() + fragments.offsets[sample],
                                      fragments.offsets[sample + 1] - fragments.offsets[sample]);
              if (clip_raster) {
                clip_ray(clip_fragments.of(sample), clip_view, clip);
                filter.clip = &clip;
              }
              ++sample;
              const Ray ray = frame.camera.ray(x + o.x, y + o.y);
              sum += run_wide_scalar(wide, [&] {
                if constexpr (std::is_invocable_v<decltype(kernel)&, const Ray&,
                                                  std::span<Fragment>, const VolumeFilter&>)
                  return kernel(ray, row, filter);
                else
                  return kernel(ray, row, filter.may_show);
              });
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
