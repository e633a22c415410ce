// Clipping of a convex camera-space polygon against half-spaces (Sutherland-Hodgman).
#pragma once
#include <array>

#include <glm/glm.hpp>

namespace imx {

// Half-space dot(plane.xyz, p) + plane.w >= 0.
using ClipPlaneEq = glm::dvec4;

inline double clip_distance(const ClipPlaneEq& plane, const glm::dvec3& p) {
  return plane.x * p.x + plane.y * p.y + plane.z * p.z + plane.w;
}

// A triangle clipped by up to kMaxPlanes planes gains at most one vertex per plane.
struct ClipPolygon {
  static constexpr int kMaxPlanes = 6;
  static constexpr int kCapacity = 2 * (3 + kMaxPlanes);  // room for rounding, see clip_polygon
  std::array<glm::dvec3, kCapacity> v;
  int n = 0;
};

// The point where edge (inside, outside) crosses the plane. Always computed from the inside end,
// so the two triangles sharing an edge get bit-identical points and stay watertight.
inline glm::dvec3 clip_crossing(const glm::dvec3& inside, double d_in, const glm::dvec3& outside,
                                double d_out) {
  double s = d_in / (d_in - d_out);
  return inside + (outside - inside) * s;
}

// Keeps the part of `poly` where clip_distance(plane, p) >= 0; n becomes 0 when nothing is left.
inline void clip_polygon(ClipPolygon& poly, const ClipPlaneEq& plane) {
  ClipPolygon out;
  // Rounding can make a clipped polygon very slightly non-convex; never write past the array.
  for (int i = 0; i < poly.n && out.n + 2 <= ClipPolygon::kCapacity; ++i) {
    const glm::dvec3& p = poly.v[i];
    const glm::dvec3& q = poly.v[(i + 1) % poly.n];
    double dp = clip_distance(plane, p), dq = clip_distance(plane, q);
    bool p_in = dp >= 0.0, q_in = dq >= 0.0;
    if (p_in) out.v[out.n++] = p;
    if (p_in && !q_in) out.v[out.n++] = clip_crossing(p, dp, q, dq);
    if (!p_in && q_in) out.v[out.n++] = clip_crossing(q, dq, p, dp);
  }
  poly = out;
}

}  // namespace imx
