#include "methods/fragment/oit.hpp"

#include "frame/fragment_context.hpp"
#include "frame/tile_base.hpp"
#include "methods/fragment/mboit_kernel.hpp"
#include "methods/fragment/wboit_kernel.hpp"

namespace imx {

Image render_wboit(const Scene& scene, int spp, const RenderOptions& options) {
  const FragmentContext ctx(scene, "wboit", true);
  return render_fragment_method(scene, ctx.frame, spp, options, FragmentOrder::arrival, [&] {
    return [&](const Ray& ray, std::span<Fragment> row, const VolumeFilter& filter) {
      return trace_wboit(ray, row, ctx.frame.volumes, ctx.frame.lights, ctx.hybrid, ctx.depth_range,
                         filter);
    };
  });
}

Image render_mboit(const Scene& scene, int spp, const RenderOptions& options) {
  const FragmentContext ctx(scene, "mboit", true);
  return render_fragment_method(scene, ctx.frame, spp, options, FragmentOrder::arrival, [&] {
    return [&](const Ray& ray, std::span<Fragment> row, const VolumeFilter& filter) {
      return trace_mboit(ray, row, ctx.frame.volumes, ctx.frame.lights, ctx.hybrid, ctx.depth_range,
                         filter);
    };
  });
}

}  // namespace imx
