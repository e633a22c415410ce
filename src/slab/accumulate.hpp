// Front-to-back accumulation of sorted slabs with early ray termination (SPEC §1).
#pragma once
#include <span>

#include <glm/vec4.hpp>

#include "slab/over.hpp"
#include "slab/slab.hpp"

namespace imx {

inline constexpr float kDefaultErtOpacity = 0.99f;

// ERT fires once the accumulated opacity reaches a_ert; a threshold of 1 or more disables it.
inline bool ert_reached(float opacity, float a_ert) {
  return a_ert < 1.0f && opacity >= a_ert;
}

struct Accumulation {
  glm::vec4 color{0.0f};    // premultiplied colour and opacity of the slabs used
  int used = 0;             // slabs composited before ERT fired (all of them otherwise)
  bool terminated = false;  // true when ERT fired
};

inline Accumulation accumulate(std::span<const Slab> slabs, float a_ert = kDefaultErtOpacity) {
  Accumulation r;
  for (const Slab& s : slabs) {
    r.color = over(r.color, s.color);
    ++r.used;
    if (ert_reached(r.color.a, a_ert)) {
      r.terminated = true;
      break;
    }
  }
  return r;
}

}  // namespace imx
