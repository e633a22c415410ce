// The first crossing of a volume's iso-value along a ray, refined by bisection (SPEC §2).
#pragma once
#include <cmath>
#include <span>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "volume/kept_span.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/range_walk.hpp"

namespace imx {

// A volume's contribution at a single depth: an iso-surface crossing or a projection (MIP, X-ray).
struct VolumeHit {
  double t = 0.0;
  glm::vec4 color{0.0f};  // premultiplied; an iso hit is shaded and has the TF's opacity there
};

// Refines a sign change of value - iso between lo and hi (f = value - iso at each) with
// `bisections` halvings and a final linear step inside the last bracket, and shades it. A
// midpoint of no data ends the halving: the bracket so far is refined linearly.
inline VolumeHit refine_iso_crossing(const PreparedVolume& v, const Ray& ray, double lo, double hi,
                                     float flo, float fhi, int bisections,
                                     std::span<const ShadingLight> lights) {
  const float iso = static_cast<float>(v.object->iso_value);
  for (int i = 0; i < bisections; ++i) {
    double mid = 0.5 * (lo + hi);
    float fm = v.grid.sample(v.to_index(ray.at(static_cast<float>(mid)))) - iso;
    if (v.has_no_data && no_data(fm)) break;
    if ((fm < 0.0f) == (flo < 0.0f)) {
      lo = mid;
      flo = fm;
    } else {
      hi = mid;
      fhi = fm;
    }
  }
  double t = flo == fhi ? 0.5 * (lo + hi) : lo + (hi - lo) * (flo / (flo - fhi));
  glm::vec3 idx = v.to_index(ray.at(static_cast<float>(t)));
  glm::vec4 tf = v.lut.lookup(iso);
  // A colour volume's surface wears its voxels' colours.
  const glm::vec3 base = v.colours.active() ? v.colours.sample(idx) : glm::vec3(tf);
  glm::vec3 rgb = blinn_phong(v.object->shading, base, v.world_gradient(idx), -ray.dir, lights);
  return {t, glm::vec4(rgb * tf.a, tf.a)};
}

// Searches [t0, t1] on the grid of points k * step (anchored at t = 0, so several volumes
// share sample positions) for the first sign change, skipping bricks whose value range lies on
// one side of the iso-value where the frame built ranges, and refines it. Returns false when
// the value never crosses. A crossing lies between two samples of data: a sample of no data
// (PreparedVolume::has_no_data) starts the search afresh after it.
namespace detail {
// find_iso_crossing with the no-data tests compiled in or out.
template <bool NoData>
bool find_iso_crossing(const PreparedVolume& v, const Ray& ray, double t0, double t1, double step,
                       int bisections, std::span<const ShadingLight> lights, VolumeHit& hit) {
  const float iso = static_cast<float>(v.object->iso_value);
  double a = 0.0, b = 0.0;
  float fa = 0.0f, fb = 0.0f;
  bool first = true, found = false;
  constexpr bool nd = NoData;
  auto visit = [&](double t, float s) {
    const float f = s - iso;
    if (nd && no_data(f)) {
      first = true;
      return true;
    }
    if (!first && (fa < 0.0f) != (f < 0.0f)) {
      b = t, fb = f, found = true;
      return false;
    }
    first = false;
    a = t, fa = f;
    return true;
  };
  // Every trilinear value in the brick is on one side: no sign change inside it.
  auto skip = [&](glm::vec2 r) { return r.x >= iso || r.y < iso; };
  auto jumped = [&](double t) {
    a = t;
    fa = v.grid.sample(v.to_index(ray.at(static_cast<float>(t)))) - iso;
    if (nd) first = no_data(fa);
  };
  walk_samples(v, ray, t0, t1, step, RangeBricks(skip_ranges(v), v, ray), visit, skip, jumped);
  if (!found) return false;
  hit = refine_iso_crossing(v, ray, a, b, fa, fb, bisections, lights);
  return true;
}
}  // namespace detail

inline bool find_iso_crossing(const PreparedVolume& v, const Ray& ray, double t0, double t1,
                              double step, int bisections, std::span<const ShadingLight> lights,
                              VolumeHit& hit) {
  return v.has_no_data
             ? detail::find_iso_crossing<true>(v, ray, t0, t1, step, bisections, lights, hit)
             : detail::find_iso_crossing<false>(v, ray, t0, t1, step, bisections, lights, hit);
}

// The first crossing within the pieces of a span that a ray keeps (clip geometry): each piece is
// searched on its own, so a piece that starts beyond the iso-value has no crossing at its start.
inline bool find_iso_crossing(const PreparedVolume& v, const Ray& ray, const KeptSpan& kept,
                              double step, int bisections, std::span<const ShadingLight> lights,
                              VolumeHit& hit) {
  for (int i = 0; i < kept.size(); ++i)
    if (find_iso_crossing(v, ray, kept[i].t0, kept[i].t1, step, bisections, lights, hit))
      return true;
  return false;
}

}  // namespace imx
