#include "methods/resident_memory.hpp"

#include "frame/frame_setup.hpp"
#include "methods/mdvr/mdvr.hpp"

namespace imx {

std::vector<std::vector<ResidentPart>> resident_parts(const Scene& scene,
                                                      const std::string& method) {
  FrameSetup frame(scene);
  // The methods whose one-volume frames march in lanes: mdvr, and zSlab with rgba32f slabs.
  const bool zslab = method == "zslab" || method == "zslab-hybrid";
  const bool lanes = method == "mdvr" || (zslab && scene.render.slab_format != "rgba8");
  const std::vector<float> steps(frame.volumes.size(),
                                 static_cast<float>(frame.ray_step(scene.render)));
  accelerate_for_packets(scene, frame, steps, lanes);
  std::vector<std::vector<ResidentPart>> parts;
  for (const PreparedVolume& v : frame.volumes) parts.push_back(resident_parts(*v.object, v.accel));
  return parts;
}

}  // namespace imx
