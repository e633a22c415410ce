#include "frame/frame_setup.hpp"

#include <algorithm>
#include <cmath>
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
  if (scene.render.pitch_mm > 0.0) min_pitch = scene.render.pitch_mm;  // a part of a scene
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

namespace {

// X-ray's average reads every value: a mean of invisible values may be visible.
bool reads_every_value(const VolumeObject& v) {
  return v.style == VolumeStyle::xray && v.xray_mode == XrayMode::average;
}

}  // namespace

void FrameSetup::accelerate(float step, const MarchSettings& settings) {
  accelerate(std::vector<float>(volumes.size(), step), settings);
}

std::vector<float> FrameSetup::volume_steps(double common, bool per_volume) const {
  std::vector<float> steps(volumes.size(), static_cast<float>(common));
  if (!per_volume) return steps;
  for (size_t k = 0; k < volumes.size(); ++k) {
    // Whole multiples only, so that every grid point of a coarse volume is one of the finest
    // volume's and their slabs stay aligned where both are sampled.
    const double ratio = std::floor(volumes[k].min_pitch / min_pitch + 1e-3);
    steps[k] = static_cast<float>(common * std::max(1.0, ratio));
  }
  return steps;
}

void FrameSetup::accelerate(std::span<const float> steps, const MarchSettings& settings) {
  coverage.clear();
  for (size_t k = 0; k < volumes.size(); ++k) {
    PreparedVolume& v = volumes[k];
    const float step = steps[k];
    if (v.object->style == VolumeStyle::dvr) {
      v.accel = imx::accelerate(*v.object, v.lut, step, settings);
    } else if (settings.skip != SkipMode::none && !reads_every_value(*v.object)) {
      // Projections and iso-surfaces skip by brick ranges only: no tables, no gradients. A ray
      // that meets no occupied brick sees only invisible values, so coverage holds for them too.
      MarchSettings ranges_only = settings;
      ranges_only.classification = Classification::post;
      ranges_only.gradients = GradientSource::on_the_fly;
      v.accel = imx::accelerate(*v.object, v.lut, step, ranges_only);
    }
    coverage.emplace_back(v, camera);
  }
}

}  // namespace imx
