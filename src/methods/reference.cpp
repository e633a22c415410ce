#include "methods/reference.hpp"

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "methods/frame_setup.hpp"
#include "methods/per_sample_render.hpp"
#include "methods/reference_kernel.hpp"

namespace imx {

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
  params.step = scene.render.step_mm > 0.0 ? scene.render.step_mm
                                           : frame.min_pitch * scene.render.reference_step_fraction;
  return render_per_sample(
      scene, frame, spp, options, [&](const Ray& ray, std::span<const Fragment> fragments) {
        return trace_reference(ray, fragments, frame.volumes, frame.lights, params);
      });
}

}  // namespace imx
