// Greedy compression criterion: which adjacent pair of slabs to merge when an array overflows.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/vec4.hpp>

#include "slab/over.hpp"
#include "slab/slab.hpp"

namespace imx {

// Cost of replacing a, b (a nearer) by `a over b`. A merged slab is read back with linear
// (OVI) interpolation, i.e. it assumes one constant accumulated-opacity gradient over its whole
// interval; the cost is the largest error that assumption makes at the old joint (a's back and
// b's front), weighted by the transmittance in front of the pair. It is zero exactly when both
// slabs raise the accumulated opacity at the same rate per unit depth (equal gradients), and
// zero for coincident surfaces, which have no depth structure to lose.
inline float merge_cost(const Slab& a, const Slab& b, float transmittance) {
  Slab m = over(a, b);
  if (!(m.thickness > 0.0f)) return 0.0f;
  float lo = m.front();
  float x_joint = std::clamp((a.t_back - lo) / m.thickness, 0.0f, 1.0f);
  float x_next = std::clamp((b.front() - lo) / m.thickness, 0.0f, 1.0f);
  float error =
      std::max(std::abs(a.color.a - x_joint * m.color.a), std::abs(a.color.a - x_next * m.color.a));
  return transmittance * error;
}

// Index i of the adjacent pair (i, i + 1) among the n >= 2 sorted slabs at(0 .. n-1) that is
// cheapest to merge; on a tie the deeper pair wins, so fully hidden slabs fold like a tail.
template <class At>
int cheapest_pair(const At& at, int n) {
  int best = n - 2;
  float best_cost = std::numeric_limits<float>::infinity();
  glm::vec4 acc(0.0f);
  for (int i = 0; i + 1 < n; ++i) {
    const Slab a = at(i);
    float cost = merge_cost(a, at(i + 1), 1.0f - acc.a);
    if (cost <= best_cost) {
      best_cost = cost;
      best = i;
    }
    acc = over(acc, a.color);
  }
  return best;
}

}  // namespace imx
