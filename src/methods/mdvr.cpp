#include "methods/mdvr.hpp"

#include "methods/frame_setup.hpp"
#include "methods/mdvr_kernel.hpp"
#include "methods/per_sample_render.hpp"

namespace imx {

Image render_mdvr(const Scene& scene, int spp, const RenderOptions& options) {
  FrameSetup frame(scene);
  frame.require_per_sample_support("mdvr");
  MdvrParams params;
  params.step =
      static_cast<float>(scene.render.step_mm > 0.0 ? scene.render.step_mm : frame.min_pitch);
  params.ert = static_cast<float>(scene.render.ert_threshold);
  frame.accelerate(params.step, MarchSettings::from(scene.render));
  return render_per_sample(scene, frame, spp, options,
                           [&](const Ray& ray, std::span<const Fragment> fragments) {
                             return trace_mdvr(ray, fragments, frame.volumes, frame.lights, params);
                           });
}

}  // namespace imx
