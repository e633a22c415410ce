#include "methods/frame_setup.hpp"

#include <algorithm>
#include <limits>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "volume/ray_volumes.hpp"

namespace imx {

FrameSetup::FrameSetup(const Scene& scene)
    : camera(scene.camera, scene.image.width, scene.image.height), clip(scene) {
  volumes.reserve(scene.volumes.size());
  double pitch = std::numeric_limits<double>::infinity();
  for (const VolumeObject& v : scene.volumes) {
    volumes.emplace_back(v);
    pitch = std::min(pitch, static_cast<double>(volumes.back().min_pitch));
  }
  if (!volumes.empty()) min_pitch = pitch;
  for (const Light& l : scene.lights) lights.push_back(resolve_light(l));
}

void FrameSetup::require_per_sample_support(const char* method) const {
  if (volumes.size() > static_cast<size_t>(kMaxRayVolumes))
    throw Error(fmt::format("{}: the scene has {} volumes, at most {} are supported", method,
                            volumes.size(), kMaxRayVolumes));
}

void FrameSetup::accelerate(float step, const MarchSettings& settings) {
  coverage.clear();
  for (PreparedVolume& v : volumes) {
    if (v.object->style == VolumeStyle::dvr)
      v.accel = imx::accelerate(*v.object, v.lut, step, settings);
    coverage.emplace_back(v, camera);
  }
}

}  // namespace imx
