#include <gtest/gtest.h>

#include "raster/clip_polygon.hpp"
#include "raster/edge_function.hpp"

namespace imx {
namespace {

int coverage(const TriangleEdges& e, int64_t x, int64_t y) {
  return e.covers(x, y) ? 1 : 0;
}

TEST(EdgeFunction, SharedDiagonalIsCoveredExactlyOnce) {
  // A square split along both of its possible diagonals, in both windings.
  const FixedPoint a{0, 0}, b{64, 0}, c{64, 64}, d{0, 64};
  const FixedPoint splits[4][2][3] = {{{a, b, c}, {a, c, d}},
                                      {{a, c, b}, {a, d, c}},
                                      {{a, b, d}, {b, c, d}},
                                      {{d, b, a}, {c, b, d}}};
  for (const auto& split : splits) {
    TriangleEdges t0, t1;
    ASSERT_TRUE(setup_triangle_edges(split[0], t0));
    ASSERT_TRUE(setup_triangle_edges(split[1], t1));
    for (int64_t y = 1; y < 64; ++y)
      for (int64_t x = 1; x < 64; ++x)
        ASSERT_EQ(coverage(t0, x, y) + coverage(t1, x, y), 1) << x << ", " << y;
  }
}

TEST(EdgeFunction, SharedVertexOfAFanIsCoveredExactlyOnce) {
  // Eight triangles around the centre (32, 32), whose edges pass through lattice points.
  const FixedPoint centre{32, 32};
  const FixedPoint ring[8] = {{64, 32}, {64, 64}, {32, 64}, {0, 64},
                              {0, 32},  {0, 0},   {32, 0},  {64, 0}};
  std::vector<TriangleEdges> fan(8);
  for (int i = 0; i < 8; ++i) {
    const FixedPoint tri[3] = {centre, ring[i], ring[(i + 1) % 8]};
    ASSERT_TRUE(setup_triangle_edges(tri, fan[i]));
  }
  for (int64_t y = 1; y < 64; ++y)
    for (int64_t x = 1; x < 64; ++x) {
      int n = 0;
      for (const TriangleEdges& t : fan) n += coverage(t, x, y);
      ASSERT_EQ(n, 1) << x << ", " << y;
    }
}

TEST(EdgeFunction, ZeroAreaIsRejectedAndOutsideIsNotCovered) {
  TriangleEdges e;
  const FixedPoint line[3] = {{0, 0}, {10, 10}, {20, 20}};
  EXPECT_FALSE(setup_triangle_edges(line, e));
  const FixedPoint tri[3] = {{0, 0}, {100, 0}, {0, 100}};
  ASSERT_TRUE(setup_triangle_edges(tri, e));
  EXPECT_TRUE(e.covers(10, 10));
  EXPECT_FALSE(e.covers(60, 60));
  EXPECT_FALSE(e.covers(-1, 10));
  EXPECT_FALSE(e.covers(10, -1));
}

TEST(ClipPolygon, KeepsTheInsideAndSharedEdgesClipIdentically) {
  const glm::dvec3 p{0.3, 0.1, -1.0}, q{0.7, 0.9, 2.0}, r{-0.4, 0.5, 3.0}, s{1.1, -0.2, 2.5};
  const ClipPlaneEq near{0.0, 0.0, 1.0, -0.25};
  ClipPolygon a, b;  // two triangles sharing edge p-q, walked in opposite directions
  a.n = b.n = 3;
  a.v[0] = p, a.v[1] = q, a.v[2] = r;
  b.v[0] = q, b.v[1] = p, b.v[2] = s;
  clip_polygon(a, near);
  clip_polygon(b, near);
  ASSERT_EQ(a.n, 4);
  ASSERT_EQ(b.n, 4);
  for (int i = 0; i < a.n; ++i) EXPECT_GE(a.v[i].z, 0.25 - 1e-12);
  // The crossing on the shared edge must be bit-identical in both polygons.
  auto crossing = [&](const ClipPolygon& poly) {
    for (int i = 0; i < poly.n; ++i) {
      glm::dvec3 d = poly.v[i] - p;
      if (std::abs(poly.v[i].z - 0.25) < 1e-12 && glm::length(glm::cross(d, q - p)) < 1e-9)
        return poly.v[i];
    }
    return glm::dvec3(1e30);
  };
  glm::dvec3 ca = crossing(a), cb = crossing(b);
  EXPECT_EQ(ca.x, cb.x);
  EXPECT_EQ(ca.y, cb.y);
  EXPECT_EQ(ca.z, cb.z);
  // Entirely outside: nothing left.
  ClipPolygon behind;
  behind.n = 3;
  behind.v[0] = {0, 0, -1}, behind.v[1] = {1, 0, -2}, behind.v[2] = {0, 1, -3};
  clip_polygon(behind, near);
  EXPECT_EQ(behind.n, 0);
}

}  // namespace
}  // namespace imx
