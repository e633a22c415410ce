// Projection styles (SPEC §2): maximum intensity (mip) and X-ray (average value) along a ray.
#pragma once
#include <cmath>

#include <glm/glm.hpp>

#include "core/ray.hpp"
#include "intermix/scene.hpp"
#include "volume/iso_crossing.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

// Samples each kept piece [t0, t1] (clip geometry; a whole span is one piece) at the points
// k * step plus both ends, and classifies the maximum (mip) or the mean over the kept length
// (xray) value with the TF, whose opacity is taken as it is: a projection is an image of the
// whole span, not a medium. The hit sits at the maximum's depth (mip) or mid-way between the
// first piece's start and the last one's end (xray), so it is composited in depth order with the
// other objects. False when nothing is kept or the TF makes it invisible.
inline bool project_volume(const PreparedVolume& v, const Ray& ray, const KeptSpan& kept,
                           double step, VolumeHit& hit) {
  if (kept.empty()) return false;
  auto value_at = [&](double t) {
    return v.grid.sample(v.to_index(ray.at(static_cast<float>(t))));
  };
  float best = 0.0f, sum = 0.0f;
  double best_t = 0.0, length = 0.0;
  for (int i = 0; i < kept.size(); ++i) {
    const double t0 = kept[i].t0, t1 = kept[i].t1;
    double prev = t0;
    float prev_value = value_at(t0);
    if (i == 0 || prev_value > best) {
      best = prev_value;
      best_t = t0;
    }
    // Trapezoids between consecutive points give the mean of the piecewise-linear profile.
    for (double k = std::floor(t0 / step) + 1.0;; k += 1.0) {
      double t = std::min(t1, k * step);
      float s = value_at(t);
      sum += 0.5f * (prev_value + s) * static_cast<float>(t - prev);
      if (s > best) {
        best = s;
        best_t = t;
      }
      prev = t;
      prev_value = s;
      if (t >= t1) break;
    }
    length += t1 - t0;
  }
  bool mip = v.object->style == VolumeStyle::mip;
  float value = mip ? best : (length > 0.0 ? sum / static_cast<float>(length) : best);
  glm::vec4 tf = v.lut.lookup(value);
  if (tf.a <= 0.0f) return false;
  hit = {mip ? best_t : 0.5 * (static_cast<double>(kept.front()) + kept.back()),
         glm::vec4(glm::vec3(tf) * tf.a, tf.a)};
  return true;
}

// The same over the whole of [t0, t1].
inline bool project_volume(const PreparedVolume& v, const Ray& ray, double t0, double t1,
                           double step, VolumeHit& hit) {
  return project_volume(
      v, ray, KeptSpan(RayInterval{static_cast<float>(t0), static_cast<float>(t1)}), step, hit);
}

}  // namespace imx
