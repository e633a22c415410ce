// mix: order-independent combination of co-located visibility (SPEC §4 pairwise, §5 M1).
#pragma once
#include <algorithm>
#include <cstdint>
#include <span>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "slab/slab.hpp"

namespace imx {

// Two aligned visibilities: A = A1 + A2 - A1 A2, C = C1 + C2 - (C1 A2 + C2 A1) / 2, the mean of
// `a over b` and `b over a`. Symmetric and free of divisions, so safe at zero opacity.
inline glm::vec4 mix(const glm::vec4& a, const glm::vec4& b) {
  glm::vec3 ca(a), cb(b);
  return {ca + cb - 0.5f * (ca * b.a + cb * a.a), a.a + b.a - a.a * b.a};
}

// Two aligned slabs; the result covers both intervals.
inline Slab mix(const Slab& a, const Slab& b) {
  return Slab::between(std::min(a.front(), b.front()), std::max(a.t_back, b.t_back),
                       mix(a.color, b.color));
}

// M1 from its sums: medium colour c = sum C / sum A, C = c A. With no opacity at all the
// scale A / sum A tends to 1, so the colours simply add (as the pairwise mix does).
inline glm::vec4 m1_visibility(const glm::vec3& colour_sum, float alpha_sum, float opacity) {
  float scale = alpha_sum > 0.0f ? opacity / alpha_sum : 1.0f;
  return {colour_sum * scale, opacity};
}

// M1 of n aligned visibilities: A = 1 - prod(1 - A_i), c = sum C_i / sum A_i; any order.
inline glm::vec4 mix_m1(std::span<const glm::vec4> v) {
  glm::vec3 colour_sum(0.0f);
  float alpha_sum = 0.0f;
  float transmittance = 1.0f;
  for (const glm::vec4& c : v) {
    colour_sum += glm::vec3(c);
    alpha_sum += c.a;
    transmittance *= 1.0f - c.a;
  }
  return m1_visibility(colour_sum, alpha_sum, 1.0f - transmittance);
}

// Exclusive mixing (SPEC §5) of n aligned visibilities: v[i] has priority rank[i] (lower ranks
// first; equal ranks form a group mixed by M1). The best-ranked group with a member whose opacity
// exceeds its threshold[i] wins alone; when none does, the worst-ranked group with any opacity
// wins (seed 004's rule for two volumes, generalized).
inline glm::vec4 mix_exclusive(std::span<const glm::vec4> v, std::span<const uint8_t> rank,
                               std::span<const float> threshold) {
  int best = 256, worst = -1;
  for (size_t i = 0; i < v.size(); ++i) {
    if (v[i].a > threshold[i]) best = std::min<int>(best, rank[i]);
    if (v[i].a > 0.0f) worst = std::max<int>(worst, rank[i]);
  }
  const int winner = best < 256 ? best : worst;
  glm::vec3 colour_sum(0.0f);
  float alpha_sum = 0.0f;
  float transmittance = 1.0f;
  for (size_t i = 0; i < v.size(); ++i)
    if (rank[i] == winner) {
      colour_sum += glm::vec3(v[i]);
      alpha_sum += v[i].a;
      transmittance *= 1.0f - v[i].a;
    }
  return m1_visibility(colour_sum, alpha_sum, 1.0f - transmittance);
}

// M1 of n aligned slabs; the result covers all their intervals (empty input: an empty slab).
inline Slab mix_m1(std::span<const Slab> slabs) {
  if (slabs.empty()) return Slab{};
  glm::vec3 colour_sum(0.0f);
  float alpha_sum = 0.0f;
  float transmittance = 1.0f;
  float lo = slabs[0].front(), hi = slabs[0].t_back;
  for (const Slab& s : slabs) {
    colour_sum += glm::vec3(s.color);
    alpha_sum += s.color.a;
    transmittance *= 1.0f - s.color.a;
    lo = std::min(lo, s.front());
    hi = std::max(hi, s.t_back);
  }
  return Slab::between(lo, hi, m1_visibility(colour_sum, alpha_sum, 1.0f - transmittance));
}

}  // namespace imx
