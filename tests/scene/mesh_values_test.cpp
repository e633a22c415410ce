// Values on meshes in scenes: "color_by" samples a volume at the vertices (checked against a
// trilinear sampling the test does itself) and "overlay" colours by per-vertex files and point
// data through a transfer function or a label table.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "core/colour.hpp"
#include "expect_error.hpp"
#include "freesurfer_files.hpp"
#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "scene/scene_from_files.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using nlohmann::json;

// ---- the test's own references

// The volume's value at world point p by trilinear interpolation of `v` (x fastest) placed by
// `index_to_world`; NaN outside the box of voxel centres.
double trilinear(const std::vector<float>& v, glm::ivec3 dims, const glm::dmat4& index_to_world,
                 glm::dvec3 p) {
  const glm::dvec3 q = glm::dvec3(glm::inverse(index_to_world) * glm::dvec4(p, 1.0));
  for (int a = 0; a < 3; ++a)
    if (!(q[a] >= -1e-9 && q[a] <= dims[a] - 1 + 1e-9)) return std::nan("");
  const glm::ivec3 i0 = glm::clamp(glm::ivec3(glm::floor(q)), glm::ivec3(0), dims - 2);
  const glm::dvec3 f = q - glm::dvec3(i0);
  double sum = 0.0;
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 i = i0 + glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    const double w =
        ((c & 1) ? f.x : 1 - f.x) * ((c & 2) ? f.y : 1 - f.y) * ((c & 4) ? f.z : 1 - f.z);
    sum += w * v[(static_cast<size_t>(i.z) * dims.y + i.y) * dims.x + i.x];
  }
  return sum;
}

// A piecewise-linear colour through points (value, r, g, b), constant beyond the ends: the
// points' display colours decoded, blended in linear light between them (docs/colour.md).
glm::dvec3 ramp(const std::vector<std::array<double, 4>>& points, double value) {
  const auto at = [&](size_t k) {
    return glm::dvec3(
        display_to_linear(glm::vec3(glm::dvec3(points[k][1], points[k][2], points[k][3]))));
  };
  if (value <= points.front()[0]) return at(0);
  for (size_t k = 1; k < points.size(); ++k)
    if (value <= points[k][0]) {
      const double t = (value - points[k - 1][0]) / (points[k][0] - points[k - 1][0]);
      return at(k - 1) + t * (at(k) - at(k - 1));
    }
  return at(points.size() - 1);
}

json tf_json(const std::vector<std::array<double, 4>>& points) {
  json p = json::array();
  for (const auto& q : points) p.push_back({q[0], q[1], q[2], q[3], 0.5});
  return {{"points", p}};
}

// A float volume of `dims` voxels at `index_to_world` (LPS) written as NIfTI: its values.
std::vector<float> write_volume_file(const std::filesystem::path& file, glm::ivec3 dims,
                                     const glm::dmat4& index_to_world, bool linear_x) {
  std::mt19937 rng(35);
  std::normal_distribution<float> noise(0.0f, 0.3f);
  std::vector<float> v(static_cast<size_t>(dims.x) * dims.y * dims.z);
  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i) {
        const glm::dvec3 w = glm::dvec3(index_to_world * glm::dvec4(i, j, k, 1.0));
        v[(static_cast<size_t>(k) * dims.y + j) * dims.x + i] =
            linear_x
                ? static_cast<float>(w.x)
                : static_cast<float>(std::sin(w.x / 7.0) + 0.5 * std::cos(w.y / 9.0) + w.z / 40.0) +
                      noise(rng);
      }
  VolumeData data;
  data.dims = dims;
  data.voxels = v;
  data.index_to_world = index_to_world;
  write_nifti(data, file, false);
  return v;
}

// 2 mm voxels turned 25 degrees about an oblique axis, centred on the origin.
glm::dmat4 oblique_grid(glm::ivec3 dims) {
  glm::dmat4 m =
      glm::rotate(glm::dmat4(1.0), glm::radians(25.0), glm::normalize(glm::dvec3(1, 2, 3)));
  m = m * glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));
  m[3] = glm::dvec4(-glm::dvec3(glm::dmat3(m) * (glm::dvec3(dims - 1) * 0.5)), 1.0);
  return m;
}

Scene load(const test::TempDir& dir, const json& scene) {
  const std::filesystem::path file = dir / "scene.json";
  test::write_bytes(file, scene.dump(2));
  return load_scene(file);
}

json volume_object(const json& extra = json::object()) {
  json o = {{"name", "tmap"},
            {"type", "volume"},
            {"source", {{"file", "tmap.nii"}}},
            {"transform", {{"translate", {2, 1, -1}}}},
            {"transfer_function", {{"points", {{-5, 0, 0, 0, 0.1}, {5, 1, 1, 1, 0.1}}}}}};
  o.update(extra);
  return o;
}

// The check: a cortex-like mesh coloured by a volume, each vertex's colour the transfer
// function of the value sampled at its position, to 1/255, for 1,000 random vertices.
TEST(MeshValues, ColorByVolumeIsTheTransferFunctionOfTheSampledValue) {
  test::TempDir dir;
  const glm::ivec3 dims(40, 36, 44);
  const glm::dmat4 grid = oblique_grid(dims);
  const std::vector<float> voxels = write_volume_file(dir / "tmap.nii", dims, grid, false);
  const std::vector<std::array<double, 4>> points = {
      {-1.5, 0.0, 0.1, 0.9}, {0.0, 0.2, 0.8, 0.2}, {0.7, 0.9, 0.6, 0.0}, {1.8, 1.0, 0.0, 0.1}};
  const json cortex = {{"name", "cortex"},
                       {"type", "mesh"},
                       {"source", {{"primitive", "sphere"}, {"radius", 28}, {"segments", 128}}},
                       {"transform", {{"translate", {3, -4, 2}}}},
                       {"color_by", {{"volume", "tmap"}, {"transfer_function", tf_json(points)}}}};
  const Scene scene = load(dir, {{"objects", {volume_object(), cortex}}});
  const Mesh& mesh = *scene.meshes.at(0).mesh;
  ASSERT_EQ(mesh.colors.size(), mesh.positions.size());
  ASSERT_GE(mesh.positions.size(), 1000u);
  const glm::dmat4 placed = glm::translate(glm::dmat4(1.0), glm::dvec3(2, 1, -1)) * grid;
  std::mt19937 rng(1);
  std::uniform_int_distribution<size_t> pick(0, mesh.positions.size() - 1);
  int sampled = 0;
  for (int n = 0; n < 1000; ++n) {
    const size_t v = pick(rng);
    const double value = trilinear(voxels, dims, placed, glm::dvec3(mesh.positions[v]));
    ASSERT_FALSE(std::isnan(value)) << "vertex " << v << " lies outside the volume";
    const glm::dvec3 want = ramp(points, value);
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(mesh.colors[v][c], want[c], 1.0 / 255.0)
          << "vertex " << v << " value " << value << " channel " << c;
    ++sampled;
  }
  EXPECT_EQ(sampled, 1000);
}

// Along the normal: in a field equal to x, max, min and mean over [0, 3] mm are x + 3 max(0, nx),
// x + 3 min(0, nx) and x + 1.5 nx; vertices outside the volume keep the material colour.
TEST(MeshValues, ColorByReducesAlongTheNormal) {
  test::TempDir dir;
  const glm::ivec3 dims(30, 30, 30);
  const glm::dmat4 grid = oblique_grid(dims);
  write_volume_file(dir / "tmap.nii", dims, grid, true);
  const std::vector<std::array<double, 4>> points = {{-60, 0, 0, 0}, {60, 1, 1, 1}};
  for (const char* reduce : {"max", "min", "mean"}) {
    const json ball = {{"name", "ball"},
                       {"type", "mesh"},
                       {"source", {{"primitive", "sphere"}, {"radius", 20}, {"segments", 48}}},
                       {"color_by",
                        {{"volume", "tmap"},
                         {"depth_mm", {0, 3}},
                         {"reduce", reduce},
                         {"transfer_function", tf_json(points)}}}};
    const json plain = volume_object({{"transform", {{"translate", {0, 0, 0}}}}});
    const Scene scene = load(dir, {{"objects", {plain, ball}}});
    const Mesh& mesh = *scene.meshes.at(0).mesh;
    ASSERT_EQ(mesh.colors.size(), mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const double x = mesh.positions[v].x, nx = mesh.normals[v].x;
      const double want = std::string(reduce) == "max"   ? x + 3 * std::max(0.0, nx)
                          : std::string(reduce) == "min" ? x + 3 * std::min(0.0, nx)
                                                         : x + 1.5 * nx;
      ASSERT_NEAR(mesh.colors[v].r, (want + 60) / 120, 1.0 / 255.0) << reduce << " vertex " << v;
    }
  }
  // A ball reaching outside the volume: its outside vertices keep the material's colour (1).
  const json big = {{"name", "big"},
                    {"type", "mesh"},
                    {"source", {{"primitive", "sphere"}, {"radius", 45}, {"segments", 32}}},
                    {"color_by", {{"volume", "tmap"}, {"transfer_function", tf_json(points)}}}};
  const Scene scene = load(dir, {{"objects", {volume_object(), big}}});
  const Mesh& mesh = *scene.meshes.at(0).mesh;
  int outside = 0;
  for (const glm::vec3& c : mesh.colors) outside += c == glm::vec3(1.0f);
  EXPECT_GT(outside, 0);
  EXPECT_LT(outside, static_cast<int>(mesh.colors.size()));
}

// ---- overlays on a FreeSurfer surface, written here byte by byte (the readers are checked
// against nibabel in tests/io)

using test::be32;
using test::write_freesurfer_curv;
using test::write_freesurfer_sphere;

TEST(MeshValues, CurvatureOverlayThroughATransferFunctionWithThreshold) {
  test::TempDir dir;
  write_freesurfer_sphere(dir / "lh.pial", 20, 24);
  const MeshFile surface = read_mesh_file(dir / "lh.pial");
  const size_t n = surface.info.file_vertices;
  std::vector<float> thickness(n);
  for (size_t i = 0; i < n; ++i) thickness[i] = 0.5f + 4.0f * static_cast<float>(i % 97) / 96.0f;
  write_freesurfer_curv(dir / "lh.thickness", thickness);
  const std::vector<std::array<double, 4>> points = {{1, 1, 0, 0}, {4, 1, 1, 0}};
  const json cortex = {
      {"name", "cortex"},
      {"type", "mesh"},
      {"source", {{"file", "lh.pial"}}},
      {"material", {{"color", {0.5, 0.5, 0.5}}}},
      {"overlay",
       {{"file", "lh.thickness"}, {"transfer_function", tf_json(points)}, {"threshold", 2.0}}}};
  const Scene scene = load(dir, {{"objects", {cortex}}});
  const Mesh& mesh = *scene.meshes.at(0).mesh;
  ASSERT_EQ(mesh.colors.size(), surface.mesh.positions.size());
  int below = 0;
  for (size_t i = 0; i < mesh.colors.size(); ++i) {
    const double value = thickness[surface.file_vertex[i]];
    const glm::dvec3 want = value < 2.0 ? glm::dvec3(1.0) : ramp(points, value);
    below += value < 2.0;
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(mesh.colors[i][c], want[c], 1e-6) << i;
  }
  EXPECT_GT(below, 0);
  EXPECT_EQ(scene.meshes[0].material.color, glm::vec3(srgb_decode(0.5f)));  // display, decoded
}

TEST(MeshValues, AnOverlayFileAfterItsSurfaceColoursItInASceneFromFiles) {
  test::TempDir dir;
  write_freesurfer_sphere(dir / "lh.pial", 12, 16);
  const size_t n = read_mesh_file(dir / "lh.pial").info.file_vertices;
  std::vector<float> curv(n), thickness(n);
  for (size_t i = 0; i < n; ++i) {
    curv[i] = static_cast<float>(i % 2 ? 0.3 : -0.2) * static_cast<float>(i % 7);
    thickness[i] = 1.0f + static_cast<float>(i % 50) / 20.0f;
  }
  write_freesurfer_curv(dir / "lh.curv", curv);
  write_freesurfer_curv(dir / "lh.thickness", thickness);
  // Signed values: cold-hot both ways; positive ones: viridis over the robust range.
  SceneDocument doc = scene_from_files({dir / "lh.pial", dir / "lh.curv"}, "left", {});
  const json& overlay = doc.json()["objects"][0]["overlay"];
  EXPECT_EQ(overlay["colormap"], "cold-hot");
  EXPECT_EQ(overlay["symmetric"], true);
  EXPECT_EQ(doc.json()["objects"].size(), 1u);  // the overlay is no object of its own
  EXPECT_FALSE(doc.scene().meshes[0].mesh->colors.empty());
  doc = scene_from_files({dir / "lh.pial", dir / "lh.thickness"}, "left", {});
  EXPECT_EQ(doc.json()["objects"][0]["overlay"]["colormap"], "viridis");
  const double lo = doc.json()["objects"][0]["overlay"]["range"][0];
  EXPECT_GE(lo, 1.0);
  // An overlay needs its surface before it; a second one for the same surface is refused.
  EXPECT_NE(test::error_of([&] {
              scene_from_files({dir / "lh.curv"}, "left", {});
            }).find("colours the mesh given before it"),
            std::string::npos);
  EXPECT_NE(
      test::error_of([&] {
        scene_from_files({dir / "lh.pial", dir / "lh.curv", dir / "lh.thickness"}, "left", {});
      }).find("has an overlay already"),
      std::string::npos);
}

TEST(MeshValues, OverlayWithAnotherVertexCountIsRefusedInOneLine) {
  test::TempDir dir;
  write_freesurfer_sphere(dir / "lh.pial", 10, 12);
  const size_t n = read_mesh_file(dir / "lh.pial").info.file_vertices;
  write_freesurfer_curv(dir / "lh.thickness", std::vector<float>(n - 1, 2.0f));
  const json cortex = {
      {"name", "cortex"},
      {"type", "mesh"},
      {"source", {{"file", "lh.pial"}}},
      {"overlay", {{"file", "lh.thickness"}, {"colormap", "hot"}, {"range", {1, 3}}}}};
  const std::string message = test::error_of([&] { load(dir, {{"objects", {cortex}}}); });
  EXPECT_NE(message.find("objects[0].overlay.file"), std::string::npos) << message;
  EXPECT_NE(message.find(fmt::format("the overlay has {} values, the mesh {} vertices", n - 1, n)),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(MeshValues, AnnotationColoursByItsOwnTable) {
  test::TempDir dir;
  write_freesurfer_sphere(dir / "lh.pial", 8, 10);
  const MeshFile surface = read_mesh_file(dir / "lh.pial");
  const auto n = static_cast<int32_t>(surface.info.file_vertices);
  // Two labels, packed as r + g << 8 + b << 16; vertex 0 has none.
  const int32_t red = 200 + (30 << 8) + (10 << 16), blue = 20 + (40 << 8) + (230 << 16);
  std::string s = be32(n);
  for (int32_t v = 0; v < n; ++v) s += be32(v) + be32(v == 0 ? 0 : (v % 2 ? red : blue));
  s += be32(1) + be32(-2) + be32(2) + be32(7) + std::string("NOFILE\0", 7) + be32(2);
  s += be32(0) + be32(4) + std::string("red\0", 4) + be32(200) + be32(30) + be32(10) + be32(0);
  s += be32(1) + be32(5) + std::string("blue\0", 5) + be32(20) + be32(40) + be32(230) + be32(0);
  test::write_bytes(dir / "lh.aparc.annot", s);
  const json cortex = {{"name", "cortex"},
                       {"type", "mesh"},
                       {"source", {{"file", "lh.pial"}}},
                       {"overlay", {{"file", "lh.aparc.annot"}}}};
  const Scene scene = load(dir, {{"objects", {cortex}}});
  const Mesh& mesh = *scene.meshes.at(0).mesh;
  for (size_t i = 0; i < mesh.colors.size(); ++i) {
    const uint32_t f = surface.file_vertex[i];
    const glm::vec3 want = f == 0  ? glm::vec3(1.0f)
                           : f % 2 ? glm::vec3(srgb_decode(200 / 255.0f), srgb_decode(30 / 255.0f),
                                               srgb_decode(10 / 255.0f))
                                   : glm::vec3(srgb_decode(20 / 255.0f), srgb_decode(40 / 255.0f),
                                               srgb_decode(230 / 255.0f));
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(mesh.colors[i][c], want[c], 1e-6) << i;
  }
  json with_tf = cortex;
  with_tf["overlay"]["transfer_function"] = tf_json({{0, 0, 0, 0}, {1, 1, 1, 1}});
  test::expect_error(
      [&] {
        load(dir, {{"objects", {with_tf}}});
      },
      {"objects[0].overlay.transfer_function", "own table"});
}

// A VTK model's point data colours it by name; a missing name lists those there are.
TEST(MeshValues, PointDataArrayOverlay) {
  test::TempDir dir;
  std::string vtk =
      "# vtk DataFile Version 4.2\n3D Slicer output. SPACE=LPS\nASCII\n"
      "DATASET POLYDATA\nPOINTS 4 float\n0 0 0 10 0 0 0 10 0 0 0 10\n"
      "POLYGONS 4 16\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
      "POINT_DATA 4\nSCALARS depth float 1\nLOOKUP_TABLE default\n0 1 2 3\n"
      "SCALARS rgb float 3\nLOOKUP_TABLE default\n0 0 0 1 1 1 0 0 0 1 1 1\n";
  test::write_bytes(dir / "tet.vtk", vtk);
  const std::vector<std::array<double, 4>> points = {{0, 0, 0, 1}, {3, 1, 0, 0}};
  json model = {{"name", "tet"},
                {"type", "mesh"},
                {"source", {{"file", "tet.vtk"}}},
                {"overlay", {{"array", "depth"}, {"transfer_function", tf_json(points)}}}};
  const Scene scene = load(dir, {{"objects", {model}}});
  const MeshFile file = read_mesh_file(dir / "tet.vtk");
  const Mesh& mesh = *scene.meshes.at(0).mesh;
  for (size_t i = 0; i < mesh.colors.size(); ++i) {
    const glm::dvec3 want = ramp(points, file.file_vertex[i]);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(mesh.colors[i][c], want[c], 1e-6) << i;
  }
  model["overlay"]["array"] = "thickness";
  test::expect_error(
      [&] {
        load(dir, {{"objects", {model}}});
      },
      {"objects[0].overlay.array", "no point data 'thickness'", "depth, rgb"});
  model["overlay"]["array"] = "rgb";
  test::expect_error([&] { load(dir, {{"objects", {model}}}); }, {"has 3 components"});
  model["overlay"]["array"] = "depth";
  model["color_by"] = {{"volume", "x"}};
  test::expect_error([&] { load(dir, {{"objects", {model}}}); }, {"not both"});
}

}  // namespace
}  // namespace imx
