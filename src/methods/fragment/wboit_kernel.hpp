// Weighted blended OIT kernel (after McGuire and Bavoil 2013): one unordered pass per pixel. The
// colours are averaged with weights that fall off with depth and grow with opacity, and the
// average is scaled by the exact total opacity 1 - prod(1 - A_i). Volume samples and volume hits
// enter as fragments at their mid depth. Pure.
#pragma once
#include <algorithm>
#include <cmath>
#include <span>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "frame/fragment_context.hpp"
#include "frame/hybrid_composite.hpp"

namespace imx {

// Weights halve every 1/kWboitFalloff of the scene's depth range: near fragments dominate
// the average, the way the nearest would dominate with sorting, within float range (2^12).
inline constexpr float kWboitFalloff = 12.0f;

// Weight of a fragment of opacity `a` at normalized depth u in [0, 1] (0 = scene's near bound).
inline float wboit_weight(float a, float u) {
  return a * std::exp2(kWboitFalloff * (1.0f - std::clamp(u, 0.0f, 1.0f)));
}

struct WeightedBlend {
  glm::vec3 colour_sum{0.0f};  // sum C_i w_i
  float alpha_sum = 0.0f;      // sum A_i w_i
  float transmittance = 1.0f;  // prod (1 - A_i), order-independent and exact

  void add(const glm::vec4& c, float t, const DepthRange& range) {
    float w = wboit_weight(c.a, (t - range.near) / (range.far - range.near));
    colour_sum += glm::vec3(c) * w;
    alpha_sum += c.a * w;
    transmittance *= 1.0f - c.a;
  }

  glm::vec4 resolve() const {
    float a = 1.0f - transmittance;
    if (!(alpha_sum > 0.0f)) return {0.0f, 0.0f, 0.0f, a};
    return {colour_sum * (a / alpha_sum), a};
  }
};

// Feeds every contribution of a ray (its fragments, volume hits and marched volume slabs) to
// `add(colour, depth)`, in no particular order.
template <class Add>
void for_each_contribution(const Ray& ray, std::span<const Fragment> fragments,
                           std::span<const PreparedVolume> volumes,
                           std::span<const ShadingLight> lights, const HybridParams& hp,
                           const RayVolumes& rv, Add&& add) {
  for (const Fragment& f : fragments) add(f.color, f.t);
  for (int i = 0; i < rv.hit_count; ++i) add(rv.hits[i].color, static_cast<float>(rv.hits[i].t));
  for (int v = 0; v < rv.count; ++v) {
    if (!rv.marched[v]) continue;
    VolumeMarcher m(volumes[v], ray, rv.kept(v), hp.step, lights);
    for (Slab s; m.next(s);) add(s.color, s.t_back - 0.5f * s.thickness);
  }
}

inline glm::vec4 trace_wboit(const Ray& ray, std::span<const Fragment> fragments,
                             std::span<const PreparedVolume> volumes,
                             std::span<const ShadingLight> lights, const HybridParams& hp,
                             const DepthRange& range, VolumeFilter filter = {}) {
  const RayVolumes rv(ray, volumes, hp.step, hp.iso_bisections, lights, filter);
  WeightedBlend blend;
  for_each_contribution(ray, fragments, volumes, lights, hp, rv,
                        [&](const glm::vec4& c, float t) { blend.add(c, t, range); });
  return blend.resolve();
}

}  // namespace imx
