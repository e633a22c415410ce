// The first crossing of a volume's iso-value along a ray, refined by bisection (SPEC §2).
#pragma once
#include <cmath>
#include <span>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "volume/kept_span.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

// A volume's contribution at a single depth: an iso-surface crossing or a projection (MIP, X-ray).
struct VolumeHit {
  double t = 0.0;
  glm::vec4 color{0.0f};  // premultiplied; an iso hit is shaded and has the TF's opacity there
};

// Searches [t0, t1] on the grid of points k * step (anchored at t = 0, so several volumes
// share sample positions), refines the first sign change with `bisections` halvings and a final
// linear step inside the last bracket. Returns false when the value never crosses.
inline bool find_iso_crossing(const PreparedVolume& v, const Ray& ray, double t0, double t1,
                              double step, int bisections, std::span<const ShadingLight> lights,
                              VolumeHit& hit) {
  float iso = static_cast<float>(v.object->iso_value);
  auto value_at = [&](double t) {
    return v.grid.sample(v.to_index(ray.at(static_cast<float>(t)))) - iso;
  };
  double a = t0;
  float fa = value_at(a);
  while (a < t1) {
    double b = std::min(t1, (std::floor(a / step) + 1.0) * step);
    if (b <= a) b = std::min(t1, a + step);
    float fb = value_at(b);
    if ((fa < 0.0f) != (fb < 0.0f)) {
      double lo = a, hi = b;
      float flo = fa, fhi = fb;
      for (int i = 0; i < bisections; ++i) {
        double mid = 0.5 * (lo + hi);
        float fm = value_at(mid);
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
      glm::vec3 rgb =
          blinn_phong(v.object->shading, glm::vec3(tf), v.world_gradient(idx), -ray.dir, lights);
      hit = {t, glm::vec4(rgb * tf.a, tf.a)};
      return true;
    }
    a = b;
    fa = fb;
  }
  return false;
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
