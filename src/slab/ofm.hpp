// OFM: order-independent merging of overlapping fragments whole (SPEC §6, M1 kept incremental).
#pragma once
#include <algorithm>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "slab/mix.hpp"
#include "slab/slab.hpp"

namespace imx {

struct MergedFragment {
  Slab slab;               // union of the merged intervals, merged premultiplied visibility
  float alpha_sum = 0.0f;  // A_sum: sum of the merged opacities

  static MergedFragment from(const Slab& s) { return {s, s.color.a}; }

  // Medium colour c = C / A of the merged medium (SPEC §5); black without opacity.
  glm::vec3 medium_color() const {
    return slab.color.a > 0.0f ? glm::vec3(slab.color) / slab.color.a : glm::vec3(0.0f);
  }

  // sum C_i = c A_sum; with no opacity C itself is that sum (the M1 limit).
  glm::vec3 colour_sum() const {
    return slab.color.a > 0.0f ? medium_color() * alpha_sum : glm::vec3(slab.color);
  }
};

// Merges two (groups of) fragments: A' = 1 - (1 - A)(1 - A_new),
// c' = (c A_sum + C_new) / (A_sum + A_new), C' = c' A', A_sum' = A_sum + A_new.
// Commutative and associative, so any arrival order gives the same fragment.
inline MergedFragment ofm_merge(const MergedFragment& acc, const MergedFragment& incoming) {
  float opacity = 1.0f - (1.0f - acc.slab.color.a) * (1.0f - incoming.slab.color.a);
  float alpha_sum = acc.alpha_sum + incoming.alpha_sum;
  glm::vec4 color = m1_visibility(acc.colour_sum() + incoming.colour_sum(), alpha_sum, opacity);
  float lo = std::min(acc.slab.front(), incoming.slab.front());
  float hi = std::max(acc.slab.t_back, incoming.slab.t_back);
  return {Slab::between(lo, hi, color), alpha_sum};
}

inline MergedFragment ofm_merge(const MergedFragment& acc, const Slab& incoming) {
  return ofm_merge(acc, MergedFragment::from(incoming));
}

}  // namespace imx
