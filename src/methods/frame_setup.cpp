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

double FrameSetup::ray_step(const RenderSettings& settings, double pitch_fraction) const {
  const bool given = settings.step_mm > 0.0;
  const double step = given ? settings.step_mm : min_pitch * pitch_fraction;
  for (const PreparedVolume& v : volumes) {
    // The longest ray through the box is at most the sum of its edges.
    const VolumeObject& object = *v.object;
    double across = 0.0;
    for (int axis = 0; axis < 3; ++axis)
      across += glm::length(glm::dvec3(object.index_to_world[axis])) *
                std::max(object.data->dims[axis] - 1, 1);
    const double steps = across / step;
    if (!(steps <= kMaxStepsPerRay))
      throw Error(fmt::format(
          "{} gives a ray step of {:g} mm: up to {:.3g} steps across volume '{}' ({:g} mm), "
          "more than the {:g} allowed; {}",
          given ? "render.step_mm"
                : fmt::format("the smallest voxel pitch ({:g} mm){}", min_pitch,
                              pitch_fraction != 1.0
                                  ? fmt::format(" times render.reference_step_fraction ({:g})",
                                                pitch_fraction)
                                  : ""),
          step, steps, object.name, across, kMaxStepsPerRay,
          given ? "raise render.step_mm" : "set a larger render.step_mm"));
  }
  return step;
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
