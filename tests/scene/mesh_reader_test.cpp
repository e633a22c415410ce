#include <filesystem>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "mesh_checks.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::error_of;

using test::shared_data;

TEST(ReadMesh, CubePlyBecomesTwelveTriangles) {
  SKIP_WITHOUT_SHARED_DATA("cube.ply");
  Mesh m = read_mesh(shared_data("cube.ply"));
  EXPECT_EQ(m.triangles.size(), 12u);  // 2 triangles and 5 quads in the file
  ASSERT_EQ(m.normals.size(), m.positions.size());
  for (const glm::vec3& p : m.positions) {
    EXPECT_TRUE(p.x == 0.0f || p.x == 1.0f);
    EXPECT_TRUE(p.y == 0.0f || p.y == 1.0f);
    EXPECT_TRUE(p.z == 0.0f || p.z == 1.0f);
  }
  EXPECT_TRUE(test::is_closed_and_oriented(m));
  EXPECT_NEAR(std::abs(test::signed_volume(m)), 1.0, 1e-6);
}

TEST(ReadMesh, BunnyHasAllItsFacesAndNormals) {
  SKIP_WITHOUT_SHARED_DATA("bunny.ply");
  Mesh m = read_mesh(shared_data("bunny.ply"));
  EXPECT_EQ(m.triangles.size(), 69451u);
  EXPECT_LE(m.positions.size(), 35947u);
  ASSERT_EQ(m.normals.size(), m.positions.size());
  // The scan has unreferenced vertices: only those that faces use need a normal.
  std::vector<bool> used(m.positions.size(), false);
  for (const glm::uvec3& t : m.triangles)
    if (t.x < used.size() && t.y < used.size() && t.z < used.size())
      used[t.x] = used[t.y] = used[t.z] = true;
  size_t unit = 0, count = 0;
  for (size_t i = 0; i < m.normals.size(); ++i) {
    count += used[i];
    unit += used[i] && std::abs(glm::length(m.normals[i]) - 1.0f) < 1e-3f;
  }
  EXPECT_GT(unit, count * 999 / 1000);
  for (const glm::uvec3& t : m.triangles) {
    ASSERT_LT(t.x, m.positions.size());
    ASSERT_LT(t.y, m.positions.size());
    ASSERT_LT(t.z, m.positions.size());
  }
}

TEST(ReadMesh, ObjWithNodeFreeGeometryAndOwnNormals) {
  test::TempDir dir;
  auto file = dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n");
  Mesh m = read_mesh(file);
  ASSERT_EQ(m.triangles.size(), 1u);
  ASSERT_EQ(m.normals.size(), 3u);
  for (const glm::vec3& n : m.normals) EXPECT_EQ(n, glm::vec3(0.0f, 0.0f, 1.0f));
}

TEST(ReadMesh, MissingFileNamesIt) {
  std::string msg = error_of([] { read_mesh("/nonexistent/implant.stl"); });
  EXPECT_CONTAINS(msg, "/nonexistent/implant.stl");
  EXPECT_CONTAINS(msg, "no such file");
}

TEST(ReadMesh, UnreadableFileNamesItAndTheReason) {
  test::TempDir dir;
  auto file = dir.write("junk.stl", "this is not an STL file at all");
  std::string msg = error_of([&] { read_mesh(file); });
  EXPECT_CONTAINS(msg, file.string());
}

TEST(ReadMesh, FileWithoutTrianglesIsAnError) {
  test::TempDir dir;
  auto file = dir.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  std::string msg = error_of([&] { read_mesh(file); });
  EXPECT_CONTAINS(msg, file.string());
}

}  // namespace
}  // namespace imx
