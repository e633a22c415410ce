#include "methods/fragment/peel.hpp"

#include <vector>

#include "frame/fragment_context.hpp"
#include "frame/tile_base.hpp"
#include "methods/fragment/peel_kernel.hpp"

namespace imx {

Image render_peel(const Scene& scene, int spp, const RenderOptions& options) {
  const FragmentContext ctx(scene, "peel", true);
  const PeelParams params{scene.render.peel_layers, scene.render.peel_rest == "unsorted"};
  return render_fragment_method(scene, ctx.frame, spp, options, FragmentOrder::arrival, [&] {
    struct Kernel {
      const FragmentContext* ctx;
      PeelParams params;
      std::vector<Slab> layers, a, b;
      glm::vec4 operator()(const Ray& ray, std::span<Fragment> row, const VolumeFilter& filter) {
        return trace_peel(ray, row, params, ctx->frame.volumes, ctx->frame.lights, ctx->hybrid,
                          layers, {a, b}, filter);
      }
    };
    // L layers, the unsorted rest and the opaque fragment
    return Kernel{&ctx, params, std::vector<Slab>(params.layers + 2),
                  std::vector<Slab>(kRayScratchSlabs), std::vector<Slab>(kRayScratchSlabs)};
  });
}

}  // namespace imx
