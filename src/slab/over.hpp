// over: front-to-back compositing of premultiplied visibility, and of slabs (SPEC §1).
#pragma once
#include <algorithm>

#include <glm/vec4.hpp>

#include "slab/slab.hpp"

namespace imx {

// (C, A) = (C1 + (1 - A1) C2, A1 + (1 - A1) A2) with `front` nearer the eye.
inline glm::vec4 over(const glm::vec4& front, const glm::vec4& back) {
  return front + (1.0f - front.a) * back;
}

// Composites two slabs into one covering both intervals (and any gap between them): the
// tail-handling and compression step. `front` is the one nearer the eye.
inline Slab over(const Slab& front, const Slab& back) {
  float lo = std::min(front.front(), back.front());
  float hi = std::max(front.t_back, back.t_back);
  return Slab::between(lo, hi, over(front.color, back.color));
}

}  // namespace imx
