#include "methods/fragment/dfb.hpp"

#include <vector>

#include "frame/fragment_context.hpp"
#include "frame/tile_base.hpp"
#include "methods/fragment/dfb_kernel.hpp"

namespace imx {

namespace {

Image render(const Scene& scene, int spp, const RenderOptions& options, bool merge) {
  const FragmentContext ctx(scene, merge ? "dfb-sfm" : "dfb", !merge);
  DfbParams p;
  p.cap = scene.render.fragment_cap;
  p.merge = merge;
  p.layers = scene.render.layers;
  return render_fragment_method(scene, ctx.frame, spp, options, FragmentOrder::arrival, [&] {
    // per tile: the ray's scratch arrays, reused by every sample of the tile
    struct Kernel {
      const FragmentContext* ctx;
      DfbParams p;
      std::vector<Slab> fragments, merged, a, b;
      glm::vec4 operator()(const Ray& ray, std::span<Fragment> row, const VolumeFilter& filter) {
        return trace_dfb(ray, row, ctx->thickness, ctx->frame.volumes, ctx->frame.lights,
                         ctx->hybrid, p, DfbScratch{fragments, merged, {a, b}}, filter);
      }
    };
    return Kernel{&ctx,
                  p,
                  std::vector<Slab>(std::max(p.cap, 1)),
                  std::vector<Slab>(std::max(p.layers, 1)),
                  std::vector<Slab>(kRayScratchSlabs),
                  std::vector<Slab>(kRayScratchSlabs)};
  });
}

}  // namespace

Image render_dfb(const Scene& scene, int spp, const RenderOptions& options) {
  return render(scene, spp, options, false);
}

Image render_dfb_sfm(const Scene& scene, int spp, const RenderOptions& options) {
  return render(scene, spp, options, true);
}

}  // namespace imx
