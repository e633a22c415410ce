// Edge functions: exact fixed-point coverage of a 2D triangle with a watertight tie rule.
#pragma once
#include <cmath>
#include <cstdint>

#include <glm/vec2.hpp>

namespace imx {

// Image positions are snapped to 1/4096 pixel so that coverage is decided in exact integers.
inline constexpr int kSubpixelBits = 12;
inline constexpr int64_t kSubpixelScale = int64_t{1} << kSubpixelBits;

struct FixedPoint {
  int64_t x = 0, y = 0;
};

inline FixedPoint snap_to_subpixel(const glm::dvec2& p) {
  return {std::llround(p.x * static_cast<double>(kSubpixelScale)),
          std::llround(p.y * static_cast<double>(kSubpixelScale))};
}

// The three edges of a triangle as E_i(x, y) = a_i x + b_i y + c_i, oriented so that the inside
// has every E_i >= 0. A sample exactly on an edge (E == 0 before biasing) is resolved as if it
// were displaced by (eps, eps^2): an edge shared by two triangles is owned by exactly one of
// them, and a shared vertex by exactly one triangle of its fan, so closed meshes stay watertight.
struct TriangleEdges {
  int64_t a[3], b[3], c[3];

  bool covers(int64_t x, int64_t y) const {
    int64_t e0 = a[0] * x + b[0] * y + c[0];
    int64_t e1 = a[1] * x + b[1] * y + c[1];
    int64_t e2 = a[2] * x + b[2] * y + c[2];
    return (e0 | e1 | e2) >= 0;  // all signs non-negative
  }
};

// Twice the signed area of triangle p[0..2]: positive when it winds counter-clockwise.
inline int64_t twice_area(const FixedPoint (&p)[3]) {
  return (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
}

// Sets up the edges of triangle p[0..2] in either winding; false when its snapped area is zero.
// Coordinates must stay below 2^29 in magnitude so that the sums of products fit in 64 bits.
inline bool setup_triangle_edges(const FixedPoint (&p)[3], TriangleEdges& out) {
  const int64_t area = twice_area(p);
  if (area == 0) return false;
  // Positive area: walk 0 -> 1 -> 2; negative: 0 -> 2 -> 1, so the inside is always E >= 0.
  const int order[3] = {0, area > 0 ? 1 : 2, area > 0 ? 2 : 1};
  for (int i = 0; i < 3; ++i) {
    const FixedPoint& from = p[order[i]];
    const FixedPoint& to = p[order[(i + 1) % 3]];
    int64_t a = -(to.y - from.y);
    int64_t b = to.x - from.x;
    // The (eps, eps^2) displacement decides ties by the sign of a, then of b.
    bool owns_ties = a > 0 || (a == 0 && b > 0);
    out.a[i] = a;
    out.b[i] = b;
    out.c[i] = -(a * from.x + b * from.y) - (owns_ties ? 0 : 1);
  }
  return true;
}

}  // namespace imx
