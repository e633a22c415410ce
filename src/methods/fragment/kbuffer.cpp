#include "methods/fragment/kbuffer.hpp"

#include <vector>

#include "frame/fragment_context.hpp"
#include "frame/tile_base.hpp"
#include "methods/fragment/kbuffer_kernel.hpp"

namespace imx {

namespace {

Image render(const Scene& scene, int spp, const RenderOptions& options, bool merge) {
  // without merging, fragments are surfaces: nothing overlaps but at one depth
  const FragmentContext ctx(scene, merge ? "kbuffer-ofm" : "kbuffer", !merge);
  const KPlusSettings p{scene.render.k, merge};
  return render_fragment_method(scene, ctx.frame, spp, options, FragmentOrder::arrival, [&] {
    struct Kernel {
      const FragmentContext* ctx;
      KPlusSettings p;
      std::vector<Slab> resolved, a, b;
      glm::vec4 operator()(const Ray& ray, std::span<Fragment> row, const VolumeFilter& filter) {
        return trace_kbuffer(ray, row, ctx->thickness, ctx->frame.volumes, ctx->frame.lights,
                             ctx->hybrid, p, KBufferScratch{resolved, {a, b}}, filter);
      }
    };
    return Kernel{&ctx, p, std::vector<Slab>(kMaxKBufferSize + 1),
                  std::vector<Slab>(kRayScratchSlabs), std::vector<Slab>(kRayScratchSlabs)};
  });
}

}  // namespace

Image render_kbuffer(const Scene& scene, int spp, const RenderOptions& options) {
  return render(scene, spp, options, false);
}

Image render_kbuffer_ofm(const Scene& scene, int spp, const RenderOptions& options) {
  return render(scene, spp, options, true);
}

}  // namespace imx
