// Vertex normals of mesh files: from the file where it has them per vertex, else angle-weighted
// with a crease angle; splitting at creases leaves the geometry (closedness, facing) alone.
#include <cmath>
#include <set>
#include <string>
#include <tuple>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "io/mesh/mesh_topology.hpp"
#include "io/mesh/vertex_normals.hpp"
#include "phantoms/mesh_primitives.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

// An OBJ file of positions and faces only.
std::string obj_of(const Mesh& m) {
  std::string out;
  for (const glm::vec3& p : m.positions) out += fmt::format("v {} {} {}\n", p.x, p.y, p.z);
  for (const glm::uvec3& t : m.triangles)
    out += fmt::format("f {} {} {}\n", t.x + 1, t.y + 1, t.z + 1);
  return out;
}

// An ASCII STL file with its (flat) facet normals, every triangle its own three vertices.
std::string stl_of(const Mesh& m) {
  std::string out = "solid s\n";
  for (const glm::uvec3& t : m.triangles) {
    glm::vec3 a = m.positions[t.x], b = m.positions[t.y], c = m.positions[t.z];
    glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    out += fmt::format(" facet normal {} {} {}\n  outer loop\n", n.x, n.y, n.z);
    for (const glm::vec3& p : {a, b, c}) out += fmt::format("   vertex {} {} {}\n", p.x, p.y, p.z);
    out += "  endloop\n endfacet\n";
  }
  return out + "endsolid s\n";
}

// The unit cube [0, 1]^3 with eight shared corners, outward-wound.
Mesh cube() {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.positions.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const unsigned faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  return m;
}

double max_radial_error_deg(const Mesh& m) {
  double worst = 0.0;
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const double c = glm::dot(glm::normalize(glm::dvec3(m.positions[i])), glm::dvec3(m.normals[i]));
    worst = std::max(worst, glm::degrees(std::acos(std::clamp(c, -1.0, 1.0))));
  }
  return worst;
}

TEST(MeshNormals, SphereWithoutNormalsGetsRadialOnes) {
  test::TempDir dir;
  const Mesh sphere = make_sphere(40.0, 32);
  const MeshFile f = read_mesh_file(dir.write("s.obj", obj_of(sphere)));
  EXPECT_FALSE(f.info.file_normals);
  EXPECT_EQ(f.mesh.positions.size(), sphere.positions.size());  // no crease: nothing split
  ASSERT_EQ(f.mesh.normals.size(), f.mesh.positions.size());
  EXPECT_LT(max_radial_error_deg(f.mesh), 0.5);
}

TEST(MeshNormals, StlFacetNormalsAreIgnoredAndTheCornersWelded) {
  test::TempDir dir;
  const Mesh sphere = make_sphere(40.0, 32);
  const MeshFile f = read_mesh_file(dir.write("s.stl", stl_of(sphere)));
  EXPECT_FALSE(f.info.file_normals);
  EXPECT_EQ(f.mesh.positions.size(), sphere.positions.size());
  EXPECT_LT(max_radial_error_deg(f.mesh), 0.5);  // facet normals would be off by ~5 degrees
}

TEST(MeshNormals, CubeKeepsItsEdgesAtSixtyDegrees) {
  test::TempDir dir;
  const auto file = dir.write("cube.obj", obj_of(cube()));
  const MeshFile f = read_mesh_file(file);
  ASSERT_EQ(f.mesh.positions.size(), 24u);  // each corner split three ways
  for (const glm::uvec3& t : f.mesh.triangles) {
    const glm::vec3 a = f.mesh.positions[t.x], b = f.mesh.positions[t.y], c = f.mesh.positions[t.z];
    const glm::vec3 face = glm::normalize(glm::cross(b - a, c - a));
    for (unsigned i : {t.x, t.y, t.z}) EXPECT_NEAR(glm::dot(f.mesh.normals[i], face), 1.0f, 1e-6f);
  }
  const MeshTopology topology = check_closed(f.mesh);
  EXPECT_TRUE(topology.closed());
  EXPECT_NEAR(topology.signed_volume, 1.0, 1e-9);
}

TEST(MeshNormals, AngleWeightingIgnoresHowAFaceIsTriangulated) {
  // With no crease every corner is smooth. Each face meets a corner at 90 degrees whether one
  // or two of its triangles touch it: angle weights give the exact diagonal, area weights
  // would lean toward the faces whose diagonal ends there.
  test::TempDir dir;
  MeshReadOptions options;
  options.crease_angle_deg = 180.0;
  const MeshFile f = read_mesh_file(dir.write("cube.obj", obj_of(cube())), options);
  ASSERT_EQ(f.mesh.positions.size(), 8u);
  for (size_t i = 0; i < 8; ++i) {
    const glm::vec3 diagonal = glm::normalize(f.mesh.positions[i] - glm::vec3(0.5f));
    EXPECT_NEAR(glm::dot(f.mesh.normals[i], diagonal), 1.0f, 1e-6f) << i;
  }
}

TEST(MeshNormals, CreaseAngleDecidesWhichEdgesSplit) {
  // A hinge of two squares folded by 50 degrees: smooth at 60, split at 40.
  const double fold = glm::radians(50.0);
  Mesh hinge;
  hinge.positions = {{0, 0, 0},
                     {0, 1, 0},
                     {1, 0, 0},
                     {1, 1, 0},
                     {float(-std::cos(fold)), 0, float(std::sin(fold))},
                     {float(-std::cos(fold)), 1, float(std::sin(fold))}};
  hinge.triangles = {{0, 2, 3}, {0, 3, 1}, {0, 1, 5}, {0, 5, 4}};
  for (auto [crease, expected] : {std::pair{60.0, 6u}, std::pair{40.0, 8u}}) {
    Mesh m = hinge;
    detail::compute_vertex_normals(m, crease);
    EXPECT_EQ(m.positions.size(), expected) << crease;
  }
}

TEST(MeshNormals, FileNormalsAreKept) {
  test::TempDir dir;
  const auto file = dir.write("n.obj",
                              "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0.6 0 0.8\n"
                              "f 1//1 2//1 3//1\n");
  const MeshFile f = read_mesh_file(file);
  EXPECT_TRUE(f.info.file_normals);
  ASSERT_EQ(f.mesh.normals.size(), 3u);
  for (const glm::vec3& n : f.mesh.normals) EXPECT_NEAR(n.x, 0.6f, 1e-6f);
}

TEST(MeshNormals, PlyVertexColoursAreMadeLinear) {
  test::TempDir dir;
  const auto file = dir.write("c.ply",
                              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                              "property float y\nproperty float z\nproperty uchar red\n"
                              "property uchar green\nproperty uchar blue\nproperty uchar alpha\n"
                              "element face 1\nproperty list uchar int vertex_indices\n"
                              "end_header\n0 0 0 255 0 0 255\n1 0 0 0 188 0 255\n"
                              "0 1 0 0 0 0 128\n3 0 1 2\n");
  const MeshFile f = read_mesh_file(file);
  EXPECT_TRUE(f.info.file_colors);
  ASSERT_EQ(f.mesh.colors.size(), f.mesh.positions.size());
  std::set<std::tuple<float, float, float>> colours;
  for (const glm::vec3& c : f.mesh.colors) colours.emplace(c.r, c.g, c.b);
  EXPECT_TRUE(colours.count({1.0f, 0.0f, 0.0f}));
  bool half = false;  // sRGB 188 is about linear 0.5
  for (const glm::vec3& c : f.mesh.colors) half = half || std::abs(c.g - 0.5f) < 0.005f;
  EXPECT_TRUE(half);
  // Transforms and flips carry the colours along.
  glm::dmat4 shift(1.0);
  shift[3] = glm::dvec4(1.0, 2.0, 3.0, 1.0);
  EXPECT_EQ(transform_mesh(f.mesh, shift).colors, f.mesh.colors);
  EXPECT_EQ(flipped(f.mesh).colors, f.mesh.colors);
}

TEST(MeshNormals, ObjVertexColoursAreMadeLinear) {
  test::TempDir dir;
  const MeshFile f = read_mesh_file(dir.write("c.obj",
                                              "v 0 0 0 1 0 0\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0 0 0 1\n"
                                              "f 1 2 3\n"));
  EXPECT_TRUE(f.info.file_colors);
  EXPECT_EQ(f.info.file_vertices, 3u);
  ASSERT_EQ(f.mesh.colors.size(), 3u);
  std::set<std::tuple<float, float, float>> colours;
  for (const glm::vec3& c : f.mesh.colors) colours.emplace(c.r, c.g, c.b);
  EXPECT_TRUE(colours.count({1.0f, 0.0f, 0.0f}));
  bool grey = false;  // sRGB 0.5 is linear 0.214
  for (const glm::vec3& c : f.mesh.colors) grey = grey || std::abs(c.g - 0.214f) < 0.001f;
  EXPECT_TRUE(grey);
}

TEST(MeshNormals, CreaseAngleOutOfRangeIsAnError) {
  test::TempDir dir;
  MeshReadOptions options;
  options.crease_angle_deg = -1.0;
  EXPECT_CONTAINS(
      test::error_of([&] { read_mesh_file(dir.write("cube.obj", obj_of(cube())), options); }),
      "crease angle -1");
}

}  // namespace
}  // namespace imx
