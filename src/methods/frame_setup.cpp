#include "methods/frame_setup.hpp"

#include <algorithm>
#include <limits>

namespace imx {

FrameSetup::FrameSetup(const Scene& scene)
    : camera(scene.camera, scene.image.width, scene.image.height) {
  volumes.reserve(scene.volumes.size());
  double pitch = std::numeric_limits<double>::infinity();
  for (const VolumeObject& v : scene.volumes) {
    volumes.emplace_back(v);
    pitch = std::min(pitch, static_cast<double>(volumes.back().min_pitch));
  }
  if (!volumes.empty()) min_pitch = pitch;
  for (const Light& l : scene.lights) lights.push_back(resolve_light(l));
}

}  // namespace imx
