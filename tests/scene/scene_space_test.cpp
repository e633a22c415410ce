// "space": "RAS" at the top of a scene: the camera, lights, planes, clip planes, inline
// transforms and the meshes that name no space are RAS. The same scene written in LPS by hand
// (x and y negated, rotations about x and y reversed) parses to the same objects, so it renders
// the same; and a mesh file with no space gets a note saying which was assumed.
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/scene.hpp"
#include "scene/scene_document.hpp"
#include "scene_fixture.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

// A box from `a` to `b` (LPS) as an ASCII PLY (no SPACE= comment), outward; `ras` writes
// each vertex in RAS (x and y negated), in the same order.
std::string box_ply(glm::dvec3 a, glm::dvec3 b, bool ras) {
  std::string s =
      "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
      "property float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n";
  const double f = ras ? -1.0 : 1.0;
  for (int i = 0; i < 8; ++i)
    s += fmt::format("{} {} {}\n", f * ((i & 1) ? b.x : a.x), f * ((i & 2) ? b.y : a.y),
                     (i & 4) ? b.z : a.z);
  const int faces[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                            {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (const auto& f : faces) s += fmt::format("3 {} {} {}\n", f[0], f[1], f[2]);
  return s;
}

// One scene in `space`; `v` writes a point or direction of it (negated x and y for RAS).
std::string scene_text(const std::string& space, bool ras) {
  auto v = [&](double x, double y, double z) {
    return fmt::format("[{}, {}, {}]", ras ? -x : x, ras ? -y : y, z);
  };
  const double sign = ras ? -1.0 : 1.0;  // rotations about x and y turn the other way
  return fmt::format(
      R"({{{}
  "camera": {{"eye": {}, "target": {}, "up": {}}},
  "image": {{"width": 32, "height": 32}},
  "lights": [{{"type": "directional", "direction": {}}}],
  "objects": [
    {{"name": "ct", "type": "volume", "source": {{"phantom": "ct-head", "size": 16}},
     "transfer_function": {{"preset": "ct-bone"}},
     "transform": {{"translate": {}, "rotate_deg": [{}, {}, 30], "scale": [1, 1.5, 0.8]}},
     "clip_planes": [{{"point": {}, "normal": {}}}]}},
    {{"name": "tilted", "type": "volume", "source": {{"phantom": "ct-head", "size": 16}},
     "transfer_function": {{"preset": "ct-bone"}},
     "transform": {{"matrix": [[0.9, -0.2, {}, {}], [0.3, 1.1, 0, {}], [0, {}, 1, 7], [0, 0, 0, 1]]}}}},
    {{"name": "box", "type": "mesh", "source": {{"file": "{}"}}}},
    {{"name": "ball", "type": "mesh", "source": {{"primitive": "sphere", "radius": 5}},
     "transform": {{"translate": {}}}}},
    {{"name": "cut", "type": "plane", "volume": "ct", "center": {}, "normal": {}, "up": {}}},
    {{"name": "fallback", "type": "plane", "volume": "ct", "normal": {}}}
  ]}})",
      space, v(120, -300, 60), v(5, -6, 7), v(0.1, 0.2, 1), v(1, 2, -1), v(10, -20, 5), sign * 10,
      sign * 20, v(2, 3, 4), v(1, 0.5, 0.2), sign * 0.1, sign * -4, sign * -6, sign * 0.1,
      ras ? "box_ras.ply" : "box_lps.ply", v(-30, 15, 2), v(3, 2, 1), v(0, 1, 0.3), v(0, 0, 1),
      v(0.2, 1, 0.1));
}

void expect_same(const glm::dvec3& a, const glm::dvec3& b, double tolerance = 1e-9) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(SceneSpace, ARasSceneParsesToTheSameObjectsAsItsLpsTwin) {
  test::TempDir dir;
  dir.write("box_lps.ply", box_ply({-10, 5, 0}, {4, 12, 9}, false));
  dir.write("box_ras.ply", box_ply({-10, 5, 0}, {4, 12, 9}, true));  // the same box in RAS
  const Scene lps = test::parse(scene_text("", false), {}, dir.path());
  const Scene ras = test::parse(scene_text(R"("space": "RAS",)", true), {}, dir.path());
  expect_same(ras.camera.eye, lps.camera.eye);
  expect_same(ras.camera.target, lps.camera.target);
  expect_same(ras.camera.up, lps.camera.up);
  ASSERT_EQ(ras.lights.size(), 1u);
  expect_same(ras.lights[0].direction, lps.lights[0].direction);
  ASSERT_EQ(ras.volumes.size(), 2u);
  for (size_t i = 0; i < 2; ++i)
    for (int c = 0; c < 4; ++c)
      expect_same(glm::dvec3(ras.volumes[i].index_to_world[c]),
                  glm::dvec3(lps.volumes[i].index_to_world[c]), 1e-9);
  ASSERT_EQ(ras.volumes[0].clip_planes.size(), 1u);
  expect_same(ras.volumes[0].clip_planes[0].point, lps.volumes[0].clip_planes[0].point);
  expect_same(ras.volumes[0].clip_planes[0].normal, lps.volumes[0].clip_planes[0].normal);
  ASSERT_EQ(ras.meshes.size(), 2u);
  for (size_t m = 0; m < 2; ++m) {
    const Mesh& a = *ras.meshes[m].mesh;
    const Mesh& b = *lps.meshes[m].mesh;
    ASSERT_EQ(a.positions.size(), b.positions.size());
    ASSERT_EQ(a.triangles, b.triangles);
    for (size_t k = 0; k < a.positions.size(); ++k) {
      expect_same(glm::dvec3(a.positions[k]), glm::dvec3(b.positions[k]), 1e-4);
      expect_same(glm::dvec3(a.normals[k]), glm::dvec3(b.normals[k]), 1e-5);
    }
  }
  ASSERT_EQ(ras.planes.size(), 2u);
  for (size_t p = 0; p < 2; ++p) {
    expect_same(ras.planes[p].center, lps.planes[p].center);
    expect_same(ras.planes[p].normal, lps.planes[p].normal);
    expect_same(ras.planes[p].up, lps.planes[p].up);
  }
  // The header-less file's space is said, and is the scene's.
  ASSERT_EQ(lps.notes.size(), 1u);
  EXPECT_EQ(lps.notes[0],
            "mesh 'box': box_lps.ply names no space (no SPACE= header) and its source no "
            "\"space\": LPS assumed (the scene's)");
  ASSERT_EQ(ras.notes.size(), 1u);
  EXPECT_CONTAINS(ras.notes[0], "RAS assumed (the scene's); converted to LPS");
}

TEST(SceneSpace, AFramedCameraIsWrittenOutInTheScenesSpace) {
  // With no camera, the note names the centre as the scene writes it.
  const Scene ras = test::parse(
      test::with_objects(test::mesh_json("ball", R"("primitive": "sphere", "radius": 5)",
                                         R"("transform": {"translate": [10, 20, 30]})"),
                         R"("space": "RAS")"));
  ASSERT_FALSE(ras.notes.empty());
  EXPECT_CONTAINS(ras.notes[0], "centre [10.0, 20.0, 30.0]");
  expect_same(ras.camera.target, {-10, -20, 30}, 1e-6);
  EXPECT_CONTAINS(test::error_of([] { test::parse(test::with_objects("", R"("space": "ras")")); }),
                  "space");
}

TEST(SceneSpace, TheFramedCameraIsWrittenOutInTheDocumentsSpace) {
  SceneDocument doc = SceneDocument::from_text(
      test::with_objects(test::mesh_json("ball", R"("primitive": "sphere", "radius": 5)",
                                         R"("transform": {"translate": [10, 20, 30]})"),
                         R"("space": "RAS")"),
      "scene.json", {}, {});
  const Camera framed = doc.scene().camera;
  doc.write_out_choices();
  const nlohmann::json& target = doc.json()["camera"]["target"];
  EXPECT_NEAR(target[0].get<double>(), 10.0, 1e-6);  // RAS, as the document gives its points
  EXPECT_NEAR(target[1].get<double>(), 20.0, 1e-6);
  // Parsed again from the written document: the same camera.
  expect_same(doc.scene().camera.eye, framed.eye);
  expect_same(doc.scene().camera.target, framed.target);
  expect_same(doc.scene().camera.up, framed.up);
}

}  // namespace
}  // namespace imx
