// Slab: a depth interval of premultiplied visibility along a ray, the unit of every method
// (zSlabs, z-thickness fragments, volume ray segments and peeled layers; SPEC §1, §4).
#pragma once
#include <algorithm>

#include <glm/vec4.hpp>

namespace imx {

struct Slab {
  float t_back = 0.0f;     // back depth along the ray, mm
  float thickness = 0.0f;  // d >= 0; a surface is a slab of d = 0 (or a virtual thickness)
  glm::vec4 color{0.0f};   // premultiplied RGB and opacity A

  float front() const { return t_back - thickness; }
  bool is_surface() const { return thickness <= 0.0f; }
  // A slab with no visibility at all is the identity of over and mix.
  bool is_empty() const { return color == glm::vec4(0.0f); }

  // The slab covering [front, back]; keeps both depths exact for the caller.
  static Slab between(float front, float back, const glm::vec4& color) {
    return Slab{back, back - front, color};
  }
};

// True when the intervals share a stretch of positive length, when a surface lies strictly
// inside the other slab, or when both are surfaces at one depth. Slabs that only touch end to
// end, and a surface on another slab's boundary, do not overlap.
inline bool overlaps(const Slab& a, const Slab& b) {
  float lo = std::max(a.front(), b.front());
  float hi = std::min(a.t_back, b.t_back);
  if (lo != hi) return lo < hi;
  if (a.is_surface() && b.is_surface()) return true;
  const Slab& solid = a.is_surface() ? b : a;
  return (a.is_surface() || b.is_surface()) && solid.front() < lo && lo < solid.t_back;
}

}  // namespace imx
