// Tests for check_closed and flipped: closedness, orientation and volume of meshes (CSG.md P3).
#include "io/mesh/mesh_topology.hpp"

#include <cmath>
#include <filesystem>
#include <numbers>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "intermix/io.hpp"
#include "phantoms/mesh_primitives.hpp"
#include "shared_data.hpp"

namespace imx {
namespace {

constexpr double kPi = std::numbers::pi;

// A unit cube with 8 shared corners and 12 triangles wound counter-clockwise from outside.
Mesh hand_made_cube() {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.emplace_back(float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1));
  m.triangles = {{0, 2, 3}, {0, 3, 1},   // z = 0, facing -z
                 {4, 5, 7}, {4, 7, 6},   // z = 1, facing +z
                 {0, 1, 5}, {0, 5, 4},   // y = 0, facing -y
                 {2, 6, 7}, {2, 7, 3},   // y = 1, facing +y
                 {0, 4, 6}, {0, 6, 2},   // x = 0, facing -x
                 {1, 3, 7}, {1, 7, 5}};  // x = 1, facing +x
  return m;
}

TEST(MeshTopology, HandMadeCubeIsClosedWithUnitVolume) {
  MeshTopology t = check_closed(hand_made_cube());
  EXPECT_TRUE(t.closed());
  EXPECT_EQ(t.open_edges, 0u);
  EXPECT_EQ(t.unpaired_edges, 0u);
  EXPECT_NEAR(t.signed_volume, 1.0, 1e-12);
}

TEST(MeshTopology, InwardCubeHasNegativeVolume) {
  Mesh inward = hand_made_cube();
  for (glm::uvec3& tri : inward.triangles) std::swap(tri.x, tri.y);
  MeshTopology t = check_closed(inward);
  EXPECT_TRUE(t.closed());
  EXPECT_NEAR(t.signed_volume, -1.0, 1e-12);
  EXPECT_NEAR(check_closed(flipped(inward)).signed_volume, 1.0, 1e-12);
}

TEST(MeshTopology, FlippedReversesWindingAndNormals) {
  Mesh box = make_box({2, 3, 4});
  Mesh f = flipped(box);
  ASSERT_EQ(f.triangles.size(), box.triangles.size());
  ASSERT_EQ(f.normals.size(), box.normals.size());
  EXPECT_EQ(f.positions, box.positions);
  EXPECT_EQ(f.triangles[0], glm::uvec3(box.triangles[0].x, box.triangles[0].z, box.triangles[0].y));
  EXPECT_EQ(f.normals[0], -box.normals[0]);
  MeshTopology t = check_closed(f);
  EXPECT_TRUE(t.closed());
  EXPECT_NEAR(t.signed_volume, -24.0, 1e-9);
  EXPECT_EQ(flipped(f).triangles, box.triangles);
}

TEST(MeshTopology, AHoleLeavesOpenEdges) {
  Mesh m = hand_made_cube();
  m.triangles.pop_back();
  MeshTopology t = check_closed(m);
  EXPECT_FALSE(t.closed());
  EXPECT_EQ(t.open_edges, 3u);
  EXPECT_EQ(t.unpaired_edges, 3u);
}

TEST(MeshTopology, OneReversedTriangleIsUnpairedButNotOpen) {
  Mesh m = hand_made_cube();
  std::swap(m.triangles[0].y, m.triangles[0].z);
  MeshTopology t = check_closed(m);
  EXPECT_FALSE(t.closed());
  EXPECT_EQ(t.open_edges, 0u);      // every edge still has two triangles
  EXPECT_EQ(t.unpaired_edges, 6u);  // its 3 edges run the same way as their neighbours', twice
}

TEST(MeshTopology, NonManifoldEdgeIsOpen) {
  // Two cubes sharing the edge x = 1, y = 1: that edge has four triangles.
  Mesh a = hand_made_cube();
  Mesh b = transform_mesh(a, glm::translate(glm::dmat4(1.0), glm::dvec3(1, 1, 0)));
  Mesh both = a;
  for (const glm::vec3& p : b.positions) both.positions.push_back(p);
  for (const glm::uvec3& tri : b.triangles) both.triangles.push_back(tri + glm::uvec3(8));
  MeshTopology t = check_closed(both);
  EXPECT_EQ(t.open_edges, 1u);
  EXPECT_EQ(t.unpaired_edges, 0u);
  EXPECT_FALSE(t.closed());
  EXPECT_NEAR(t.signed_volume, 2.0, 1e-12);
}

TEST(MeshTopology, WeldsSeamsAndSkipsCollapsedTriangles) {
  Mesh m = hand_made_cube();
  // A duplicate of corner 7 used by the last triangle: a seam that welding must close.
  m.positions.push_back(m.positions[7]);
  m.triangles.back().y = 8;
  m.triangles.push_back({3, 3, 5});  // collapsed to an edge
  m.triangles.push_back({8, 7, 6});  // collapses after welding
  MeshTopology t = check_closed(m);
  EXPECT_TRUE(t.closed()) << t.open_edges << " open, " << t.unpaired_edges << " unpaired";
  EXPECT_NEAR(t.signed_volume, 1.0, 1e-12);
}

TEST(MeshTopology, NegativeZeroWeldsWithZero) {
  // Corner 0 is the origin; a copy written as -0 must still be the same point.
  Mesh m = hand_made_cube();
  m.positions.emplace_back(-0.0f, 0.0f, -0.0f);
  m.triangles[0].x = 8;
  EXPECT_TRUE(check_closed(m).closed());
}

TEST(MeshTopology, BadIndicesAreNotClosed) {
  Mesh m = hand_made_cube();
  m.triangles.push_back({0, 1, 99});
  EXPECT_FALSE(check_closed(m).closed());
}

TEST(MeshTopology, EveryClosedPrimitiveIsClosedAndFacesOutward) {
  const double r = 10.0, h = 30.0;
  const int n = 64;
  // The box exactly; the others are inscribed polyhedra, a little smaller than the solid.
  MeshTopology box = check_closed(make_box({2, 3, 4}));
  EXPECT_TRUE(box.closed());
  EXPECT_NEAR(box.signed_volume, 24.0, 1e-9);

  MeshTopology cylinder = check_closed(make_cylinder(r, h, n));
  EXPECT_TRUE(cylinder.closed());
  const double polygon_area = 0.5 * n * r * r * std::sin(2.0 * kPi / n);
  EXPECT_NEAR(cylinder.signed_volume, polygon_area * h, 1e-6 * polygon_area * h);

  MeshTopology sphere = check_closed(make_sphere(r, n));
  EXPECT_TRUE(sphere.closed());
  const double ball = 4.0 / 3.0 * kPi * r * r * r;
  EXPECT_LT(sphere.signed_volume, ball);
  EXPECT_GT(sphere.signed_volume, 0.99 * ball);

  MeshTopology torus = check_closed(make_torus(20.0, 5.0, n));
  EXPECT_TRUE(torus.closed());
  const double ring = 2.0 * kPi * kPi * 20.0 * 5.0 * 5.0;
  EXPECT_LT(torus.signed_volume, ring);
  EXPECT_GT(torus.signed_volume, 0.98 * ring);

  // Coarse tessellations too: the seams and poles weld at any segment count.
  for (int segments : {3, 4, 7}) {
    EXPECT_TRUE(check_closed(make_sphere(r, segments)).closed()) << segments;
    EXPECT_TRUE(check_closed(make_cylinder(r, h, segments)).closed()) << segments;
    EXPECT_TRUE(check_closed(make_torus(20.0, 5.0, segments)).closed()) << segments;
    EXPECT_GT(check_closed(make_sphere(r, segments)).signed_volume, 0.0) << segments;
  }
}

TEST(MeshTopology, QuadIsOpen) {
  MeshTopology t = check_closed(make_quad({4, 6}));
  EXPECT_FALSE(t.closed());
  EXPECT_EQ(t.open_edges, 4u);  // the rim; the diagonal is shared by both triangles
  EXPECT_EQ(t.unpaired_edges, 4u);
  EXPECT_EQ(t.signed_volume, 0.0);
}

TEST(MeshTopology, MirroringTransformKeepsTheVolumePositive) {
  // transform_mesh reverses the winding when the determinant is negative, so a mirrored
  // primitive still faces outward.
  const glm::dmat4 mirror = glm::scale(glm::dmat4(1.0), glm::dvec3(-1.0, 2.0, 1.0));
  MeshTopology t = check_closed(transform_mesh(make_cylinder(10.0, 30.0, 32), mirror));
  EXPECT_TRUE(t.closed());
  EXPECT_GT(t.signed_volume, 0.0);
  EXPECT_NEAR(t.signed_volume, 2.0 * check_closed(make_cylinder(10.0, 30.0, 32)).signed_volume,
              1e-6);

  // Mirroring the positions alone (as a file written by a left-handed tool would) turns it
  // inside out; flipped repairs it.
  Mesh raw = make_box({2, 3, 4});
  for (glm::vec3& p : raw.positions) p.x = -p.x;
  MeshTopology inside_out = check_closed(raw);
  EXPECT_TRUE(inside_out.closed());
  EXPECT_NEAR(inside_out.signed_volume, -24.0, 1e-9);
  EXPECT_NEAR(check_closed(flipped(raw)).signed_volume, 24.0, 1e-9);
}

TEST(MeshTopology, VolumeFarFromTheOriginStaysAccurate) {
  Mesh far = transform_mesh(make_box({2, 3, 4}),
                            glm::translate(glm::dmat4(1.0), glm::dvec3(4096.0, -8192.0, 2048.0)));
  EXPECT_NEAR(check_closed(far).signed_volume, 24.0, 1e-6);
}

TEST(MeshTopology, EmptyMeshEnclosesNothing) {
  MeshTopology t = check_closed(Mesh{});
  EXPECT_EQ(t.open_edges, 0u);
  EXPECT_EQ(t.signed_volume, 0.0);
}

TEST(MeshTopology, SharedCubePlyIsClosed) {
  SKIP_WITHOUT_SHARED_DATA("cube.ply");
  MeshTopology t = check_closed(read_mesh(test::shared_data("cube.ply")));
  EXPECT_TRUE(t.closed()) << t.open_edges << " open, " << t.unpaired_edges << " unpaired";
  EXPECT_NEAR(t.signed_volume, 1.0, 1e-9);  // a unit cube of quads, wound outward
}

TEST(MeshTopology, SharedBunnyPlyHasHoles) {
  SKIP_WITHOUT_SHARED_DATA("bunny.ply");
  MeshTopology t = check_closed(read_mesh(test::shared_data("bunny.ply")));
  RecordProperty("open_edges", static_cast<int>(t.open_edges));
  RecordProperty("unpaired_edges", static_cast<int>(t.unpaired_edges));
  // The Stanford scan has holes in its base, so CSG must refuse it.
  EXPECT_FALSE(t.closed());
  EXPECT_GT(t.open_edges, 0u);
}

}  // namespace
}  // namespace imx
