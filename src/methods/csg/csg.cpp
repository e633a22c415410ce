#include "methods/csg/csg.hpp"

#include <vector>

#include "frame/csg_frame.hpp"
#include "frame/frame_setup.hpp"
#include "frame/mixing_plan.hpp"
#include "frame/tile_base.hpp"
#include "methods/csg/csg_kernel.hpp"
#include "methods/mdvr/mdvr.hpp"

namespace imx {

Image render_csg(const Scene& scene, int spp, const RenderOptions& options) {
  // Without an expression nothing is clipped: the kernel is then mdvr's, and so is the image
  // (`bench --variant "plain:csg=null"` times the baseline from the same file). mdvr mixes
  // inclusively only.
  if (!scene.csg && scene.render.mixing != "exclusive") return render_mdvr(scene, spp, options);
  FrameSetup frame(scene);
  frame.require_per_sample_support("csg");
  const MdvrParams params = prepare_mdvr(scene, frame, false);  // csg steps and skips as mdvr does
  const CsgFrame csg(scene, frame, /*with_states=*/true);
  const CsgView view = csg.view();
  const MixingPlan mixing(scene);
  return render_fragment_method(scene, frame, spp, options, FragmentOrder::depth, [&] {
    // Per tile: the scratch rows grow to the longest fragment row and are reused.
    return [&, surfaces = std::vector<Fragment>(), ranges = std::vector<CsgRange>()](
               const Ray& ray, std::span<Fragment> row, VolumeMask may_show) mutable {
      if (surfaces.size() < row.size()) surfaces.resize(row.size());
      if (ranges.size() < csg_range_capacity(row.size()))
        ranges.resize(csg_range_capacity(row.size()));
      return trace_csg(ray, row, frame.volumes, frame.lights, params, view, mixing.view(),
                       {surfaces, ranges}, may_show);
    };
  });
}

}  // namespace imx
