// Projection styles (SPEC §2): maximum (mip) and minimum (minip) intensity, and X-ray, the line
// integral of the TF's attenuation (or, as an option, the TF at the mean value) along a ray.
#pragma once
#include <cmath>

#include <glm/glm.hpp>

#include "core/ray.hpp"
#include "intermix/scene.hpp"
#include "volume/iso_crossing.hpp"
#include "volume/kept_span.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/range_walk.hpp"

namespace imx {

// Samples each kept piece [t0, t1] (clip geometry; a whole span is one piece) at t0, the points
// k * step and t1, skipping bricks that cannot change the result where the frame built ranges:
// - mip / minip: the TF at the largest / smallest value; bricks whose max / min cannot beat the
//   running value are skipped, and the walk stops once the TF no longer changes beyond it. The
//   hit sits at that value's first depth.
// - xray: I = 1 - exp(-sum mu dt) by trapezoids over the attenuation mu, coloured by the
//   attenuation-weighted TF colour; TF-empty bricks (mu = 0) are skipped. With xray_mode
//   average, the TF at the mean value over the kept length, its opacity taken as it is.
// An X-ray hit sits mid-way between the first piece's start and the last one's end, so that it
// is composited in depth order with the other objects. False when nothing is kept or the result
// is invisible. Samples of no data (PreparedVolume::has_no_data) are never the maximum or the
// minimum, add no attenuation (as a value of opacity 0 would) and are left out of the average.
namespace detail {
// project_volume with the no-data tests compiled in or out (volumes without NaN or inf voxels
// never pay for them).
template <bool NoData>
bool project_volume(const PreparedVolume& v, const Ray& ray, const KeptSpan& kept, double step,
                    VolumeHit& hit) {
  if (kept.empty()) return false;
  const VolumeStyle style = v.object->style;
  const RangeBricks bricks(skip_ranges(v), v, ray);
  const auto no_jump = [](double) {};
  constexpr bool nd = NoData;
  glm::vec4 tf(0.0f);
  double depth = 0.5 * (static_cast<double>(kept.front()) + kept.back());
  if (style == VolumeStyle::mip || style == VolumeStyle::minip) {
    const bool max = style == VolumeStyle::mip;
    const ProjectionLimits& l = v.limits;
    float best = max ? l.invisible_up_to : l.invisible_from;
    double best_t = kept.front();
    auto visit = [&](double t, float s) {
      if (nd && no_data(s)) return true;
      if (max ? s > best : s < best) best = s, best_t = t;
      return max ? !(best >= l.constant_from) : !(best <= l.constant_up_to);
    };
    auto skip = [&](glm::vec2 r) { return max ? r.y <= best : r.x >= best; };
    for (int i = 0; i < kept.size(); ++i)
      if (!walk_samples(v, ray, kept[i].t0, kept[i].t1, step, bricks, visit, skip, no_jump)) break;
    tf = v.lut.lookup(best);
    depth = best_t;
  } else if (v.object->xray_mode == XrayMode::integral) {
    glm::vec4 sum(0.0f), prev(0.0f);  // (mu r, mu g, mu b, mu) integrated, and at the last point
    double prev_t = 0.0;
    bool first = true;
    auto visit = [&](double t, float s) {
      const glm::vec4 e = nd && no_data(s) ? glm::vec4(0.0f) : v.attenuation.lookup(s);
      if (!first) sum += (0.5f * static_cast<float>(t - prev_t)) * (prev + e);
      first = false;
      prev = e, prev_t = t;
      return true;
    };
    auto skip = [&](glm::vec2 r) {
      return !BrickMinMax::holds_data(r) || v.accel.emptiness->is_empty_between(r.x, r.y);
    };
    auto jumped = [&](double t) { prev = glm::vec4(0.0f), prev_t = t; };  // mu is 0 in the brick
    for (int i = 0; i < kept.size(); ++i) {
      first = true;
      walk_samples(v, ray, kept[i].t0, kept[i].t1, step, bricks, visit, skip, jumped);
    }
    if (!(sum.a > 0.0f)) return false;
    const float opacity = -std::expm1(-sum.a);
    tf = glm::vec4(glm::vec3(sum) / sum.a, opacity);
  } else {
    float sum = 0.0f, prev = 0.0f, length = 0.0f;
    float missing = 0.0f, last = 0.0f;  // the length of steps with no data at an end; a value
    bool any = !nd;                     // whether some sample had data
    double prev_t = 0.0;
    bool first = true;
    auto visit = [&](double t, float s) {
      const bool data = !(nd && no_data(s));
      if (!first) {
        if (data && !(nd && no_data(prev)))
          sum += 0.5f * (prev + s) * static_cast<float>(t - prev_t);
        else
          missing += static_cast<float>(t - prev_t);
      }
      if (data) any = true, last = s;
      first = false;
      prev = s, prev_t = t;
      return true;
    };
    for (int i = 0; i < kept.size(); ++i) {
      first = true;
      walk_samples(
          v, ray, kept[i].t0, kept[i].t1, step, RangeBricks(), visit,
          [](glm::vec2) { return false; }, no_jump);
      length += kept[i].t1 - kept[i].t0;
    }
    if (!any) return false;
    length -= missing;
    tf = v.lut.lookup(length > 0.0f ? sum / length : nd ? last : prev);
  }
  if (!(tf.a > 0.0f)) return false;
  hit = {depth, glm::vec4(glm::vec3(tf) * tf.a, tf.a)};
  return true;
}
}  // namespace detail

inline bool project_volume(const PreparedVolume& v, const Ray& ray, const KeptSpan& kept,
                           double step, VolumeHit& hit) {
  return v.has_no_data ? detail::project_volume<true>(v, ray, kept, step, hit)
                       : detail::project_volume<false>(v, ray, kept, step, hit);
}

// The same over the whole of [t0, t1].
inline bool project_volume(const PreparedVolume& v, const Ray& ray, double t0, double t1,
                           double step, VolumeHit& hit) {
  return project_volume(
      v, ray, KeptSpan(RayInterval{static_cast<float>(t0), static_cast<float>(t1)}), step, hit);
}

}  // namespace imx
