// Mesh files in RAS or LPS: 3D Slicer's SPACE= header comments, the "space" key, scene notes.
#include <cstring>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "intermix/io.hpp"
#include "io/mesh/mesh_topology.hpp"
#include "scene_fixture.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::error_of;

// A tetrahedron off the origin (so that negating x and y moves it), outward-wound.
const glm::vec3 kTetra[4] = {{10, 20, 30}, {11, 20, 30}, {10, 21, 30}, {10, 20, 31}};
const unsigned kFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

std::string ascii_stl(const std::string& solid_line) {
  std::string s = solid_line + "\n";
  for (const auto& f : kFaces) {
    s += " facet normal 0 0 0\n  outer loop\n";
    for (unsigned i : f)
      s += "   vertex " + std::to_string(kTetra[i].x) + " " + std::to_string(kTetra[i].y) + " " +
           std::to_string(kTetra[i].z) + "\n";
    s += "  endloop\n endfacet\n";
  }
  return s + "endsolid\n";
}

std::string binary_stl(const std::string& header) {
  std::string s(80, ' ');
  std::memcpy(s.data(), header.data(), std::min<size_t>(80, header.size()));
  uint32_t n = 4;
  s.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& f : kFaces) {
    float normal[3] = {0, 0, 0};
    s.append(reinterpret_cast<const char*>(normal), 12);
    for (unsigned i : f) s.append(reinterpret_cast<const char*>(&kTetra[i]), 12);
    s.append(2, '\0');
  }
  return s;
}

std::string obj(const std::string& first_lines, const std::string& later = "") {
  std::string s = first_lines;
  for (const glm::vec3& p : kTetra)
    s += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  s += later;
  for (const auto& f : kFaces)
    s += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " +
         std::to_string(f[2] + 1) + "\n";
  return s;
}

std::string ply(const std::string& comments) {
  std::string s = "ply\nformat ascii 1.0\n" + comments +
                  "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                  "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
  for (const glm::vec3& p : kTetra)
    s += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  for (const auto& f : kFaces)
    s += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) +
         "\n";
  return s;
}

// True when every vertex lies at a tetrahedron corner mapped by (x, y, z) -> (sx x, sy y, z).
bool at_corners(const Mesh& m, float s) {
  for (const glm::vec3& p : m.positions) {
    bool found = false;
    for (const glm::vec3& c : kTetra) found = found || p == glm::vec3(s * c.x, s * c.y, c.z);
    if (!found) return false;
  }
  return !m.positions.empty();
}

void expect_space(const std::filesystem::path& file, MeshSpace space, MeshSpaceSource source) {
  SCOPED_TRACE(file.string());
  const MeshFile f = read_mesh_file(file);
  EXPECT_EQ(f.info.space, space);
  EXPECT_EQ(f.info.space_source, source);
  EXPECT_TRUE(at_corners(f.mesh, space == MeshSpace::ras ? -1.0f : 1.0f));
  // RAS -> LPS is a rotation: the tetrahedron stays closed and outward facing.
  const MeshTopology topology = check_closed(f.mesh);
  EXPECT_TRUE(topology.closed());
  EXPECT_NEAR(topology.signed_volume, 1.0 / 6.0, 1e-4);
}

TEST(MeshSpace, SlicerHeaderCommentsNameTheSpace) {
  test::TempDir dir;
  expect_space(dir.write("ascii.stl", ascii_stl("solid 3D Slicer output. SPACE=RAS")),
               MeshSpace::ras, MeshSpaceSource::header);
  expect_space(dir.write("lps.stl", ascii_stl("solid 3D Slicer output. SPACE=LPS")), MeshSpace::lps,
               MeshSpaceSource::header);
  expect_space(dir.write("binary.stl", binary_stl("3D Slicer output. SPACE=RAS")), MeshSpace::ras,
               MeshSpaceSource::header);
  dir.write("x.mtl", "newmtl m\nKd 1 1 1\n");
  expect_space(dir.write("slicer.obj", obj("# 3D Slicer output. SPACE=RAS\n\nmtllib x.mtl\n")),
               MeshSpace::ras, MeshSpaceSource::header);
  expect_space(dir.write("slicer.ply", ply("comment VTK generated PLY File\ncomment SPACE=RAS\n")),
               MeshSpace::ras, MeshSpaceSource::header);
  expect_space(dir.write("lps.ply", ply("comment SPACE=LPS\n")), MeshSpace::lps,
               MeshSpaceSource::header);
}

TEST(MeshSpace, WithoutAHeaderCommentTheSpaceIsLps) {
  test::TempDir dir;
  expect_space(dir.write("plain.stl", ascii_stl("solid tetra")), MeshSpace::lps,
               MeshSpaceSource::assumed);
  expect_space(dir.write("plain.ply", ply("comment made by hand\n")), MeshSpace::lps,
               MeshSpaceSource::assumed);
  // Only the comments that open an OBJ file are its header.
  expect_space(dir.write("late.obj", obj("# a tetrahedron\n", "# SPACE=RAS\n")), MeshSpace::lps,
               MeshSpaceSource::assumed);
  // A binary STL's header is its first 80 bytes: the tag past them is triangle data.
  expect_space(dir.write("long.stl", binary_stl(std::string(75, 'x') + "SPACE=RAS")),
               MeshSpace::lps, MeshSpaceSource::assumed);
}

TEST(MeshSpace, TheOptionOverridesTheHeader) {
  test::TempDir dir;
  const auto file = dir.write("ras.stl", ascii_stl("solid 3D Slicer output. SPACE=RAS"));
  MeshReadOptions options;
  options.space = MeshSpace::lps;
  const MeshFile f = read_mesh_file(file, options);
  EXPECT_EQ(f.info.space_source, MeshSpaceSource::option);
  EXPECT_TRUE(at_corners(f.mesh, 1.0f));
  options.space = MeshSpace::ras;
  EXPECT_TRUE(at_corners(read_mesh_file(dir.write("plain.stl", ascii_stl("solid x")), options).mesh,
                         -1.0f));
}

TEST(MeshSpace, SceneNotesASpaceTakenFromTheHeader) {
  test::TempDir dir;
  dir.write("cortex.stl", ascii_stl("solid 3D Slicer output. SPACE=RAS"));
  const std::string objects =
      R"({"camera": {"eye": [0, -100, 0]},
          "objects": [{"name": "cortex", "type": "mesh", "source": {"file": "cortex.stl"}},
                      {"name": "again", "type": "mesh", "source": {"file": "cortex.stl"}},
                      {"name": "forced", "type": "mesh",
                       "source": {"file": "cortex.stl", "space": "LPS"}}]})";
  const Scene scene = test::parse(objects, {}, dir.path());
  ASSERT_EQ(scene.meshes.size(), 3u);
  EXPECT_TRUE(at_corners(*scene.meshes[0].mesh, -1.0f));
  EXPECT_TRUE(at_corners(*scene.meshes[1].mesh, -1.0f));
  EXPECT_TRUE(at_corners(*scene.meshes[2].mesh, 1.0f));
  ASSERT_EQ(scene.notes.size(), 1u);  // the file is read once with its own space, once forced
  EXPECT_EQ(scene.notes[0], "mesh 'cortex': cortex.stl says SPACE=RAS; converted to LPS");
}

TEST(MeshSpace, BadSpaceKeysAreErrors) {
  test::TempDir dir;
  dir.write("t.stl", ascii_stl("solid t"));
  auto scene = [](const std::string& source) {
    return R"({"objects": [{"name": "m", "type": "mesh", "source": )" + source + "}]}";
  };
  EXPECT_CONTAINS(test::parse_error(scene(R"({"file": "t.stl", "space": "XYZ"})"), {}, dir.path()),
                  "XYZ");
  EXPECT_CONTAINS(
      test::parse_error(scene(R"({"primitive": "sphere", "radius": 5, "space": "RAS"})")),
      "\"space\" applies to mesh files");
  EXPECT_CONTAINS(
      test::parse_error(scene(R"({"file": "t.stl", "crease_angle_deg": 200})"), {}, dir.path()),
      "crease_angle_deg");
  EXPECT_CONTAINS(test::parse_error(scene(R"({"file": "t.stl", "spcae": "RAS"})"), {}, dir.path()),
                  "space");
}

}  // namespace
}  // namespace imx
