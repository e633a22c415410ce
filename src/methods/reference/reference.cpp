#include "methods/reference/reference.hpp"

#include <optional>

#include "frame/csg_frame.hpp"
#include "frame/frame_setup.hpp"
#include "frame/mixing_plan.hpp"
#include "frame/ray_base.hpp"
#include "methods/reference/reference_kernel.hpp"

namespace imx {

Image render_reference(const Scene& scene, int spp, const RenderOptions& options) {
  FrameSetup frame(scene);
  frame.require_per_sample_support("reference");
  ReferenceParams params;
  params.step = frame.ray_step(scene.render, scene.render.reference_step_fraction);
  const MixingPlan mixing(scene);
  params.mixing = mixing.view();
  std::optional<CsgFrame> csg;
  if (scene.csg) csg.emplace(scene, frame, /*with_states=*/false);
  const std::optional<CsgView> csg_view = csg ? std::optional(csg->view()) : std::nullopt;
  // The volume mask is all ones: the reference builds no skipping structures (no accelerate());
  // what clip geometry keeps of each volume it takes from the filter.
  return render_per_sample(
      scene, frame, spp, options,
      [&](const Ray& ray, std::span<const Fragment> fragments, const VolumeFilter& filter) {
        return trace_reference(ray, fragments, frame.volumes, frame.lights, params,
                               csg_view ? &*csg_view : nullptr, filter);
      });
}

}  // namespace imx
