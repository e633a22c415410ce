#include <cmath>
#include <filesystem>

#include <sys/stat.h>

#include <gtest/gtest.h>

#include "core/colour.hpp"
#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "mesh_checks.hpp"
#include "scene_fixture.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::error_of;
using test::parse;
using test::parse_error;

using test::with_objects;

const std::string kSphere = test::mesh_json("ball");
const std::string kPlane =
    R"({"name": "cut", "type": "plane", "center": [0, 0, 5], "normal": [0, 0, 2], "size": 50})";

glm::dvec3 centroid(const Mesh& m) {
  glm::dvec3 sum(0.0);
  for (const glm::vec3& p : m.positions) sum += glm::dvec3(p);
  return sum / static_cast<double>(m.positions.size());
}

// ---- valid scenes -------------------------------------------------------------------------

TEST(ParseScene, MinimalSceneHasDefaults) {
  Scene s = parse(R"({"objects": []})");
  EXPECT_EQ(s.image.width, 512);
  EXPECT_EQ(s.camera.fov_deg, 30.0);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type, LightType::headlight);
  EXPECT_EQ(s.render.method, "auto");  // resolve_method picks by content
  EXPECT_TRUE(s.order.empty());
  EXPECT_TRUE(s.file.empty());
}

TEST(ParseScene, SceneWideSettings) {
  Scene s = parse(R"({
    "description": "settings",
    "camera": {"eye": [0, -500, 0], "target": [0, 0, 10], "up": [0, 0, 3], "fov_deg": 40,
               "projection": "orthographic", "ortho_height": 150},
    "image": {"width": 320, "height": 200, "background": [0.1, 0.2, 0.3]},
    "lights": [{"type": "directional", "direction": [0, 0, -2], "intensity": 0.5,
                "color": [1, 0.5, 0]}, {"type": "headlight"}],
    "render": {"method": "zslab-hybrid", "spp": 9, "step_mm": 0.5, "reference_step_fraction": 0.25,
               "ert_threshold": 1, "layers": 16, "rt_layers": 2, "peel_layers": 6,
               "peel_rest": "unsorted", "interpolation": "blend", "beta": 0.5},
    "objects": []
  })");
  EXPECT_EQ(s.camera.eye, glm::dvec3(0, -500, 0));
  EXPECT_EQ(s.camera.up, glm::dvec3(0, 0, 1));
  EXPECT_EQ(s.camera.projection, Projection::orthographic);
  EXPECT_EQ(s.camera.ortho_height, 150.0);
  EXPECT_EQ(s.image.width, 320);
  EXPECT_EQ(s.image.height, 200);
  // A display colour, decoded; alpha as given (docs/colour.md).
  EXPECT_EQ(s.image.background,
            glm::vec4(srgb_decode(0.1f), srgb_decode(0.2f), srgb_decode(0.3f), 1.0f));
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].type, LightType::directional);
  EXPECT_EQ(s.lights[0].direction, glm::dvec3(0, 0, -1));
  EXPECT_EQ(s.lights[0].intensity, 0.5f);
  EXPECT_EQ(s.lights[1].type, LightType::headlight);
  EXPECT_EQ(s.render.method, "zslab-hybrid");
  EXPECT_EQ(s.render.spp, 9);
  EXPECT_EQ(s.render.step_mm, 0.5);
  EXPECT_EQ(s.render.reference_step_fraction, 0.25);
  EXPECT_EQ(s.render.ert_threshold, 1.0);
  EXPECT_EQ(s.render.layers, 16);
  EXPECT_EQ(s.render.rt_layers, 2);
  EXPECT_EQ(s.render.peel_layers, 6);
  EXPECT_EQ(s.render.peel_rest, "unsorted");
  EXPECT_EQ(s.render.interpolation, "blend");
  EXPECT_EQ(s.render.beta, 0.5);
}

TEST(ParseScene, EmptyLightsMeansAmbientOnly) {
  EXPECT_TRUE(parse(R"({"lights": [], "objects": []})").lights.empty());
}

TEST(ParseScene, MeshPrimitivesWithTransformAndMaterial) {
  Scene s = parse(with_objects(R"(
    {"name": "ball", "type": "mesh", "source": {"primitive": "sphere", "radius": 10, "segments": 16},
     "transform": {"translate": [100, 0, 0]},
     "material": {"color": [1, 0, 0], "opacity": 0.5, "shading": {"specular": 0, "shininess": 8}},
     "thickness": 2},
    {"name": "brick", "type": "mesh", "source": {"primitive": "box", "size": [1, 2, 3]},
     "thickness": "auto", "material": {"shading": {"enabled": false}}},
    {"name": "can", "type": "mesh", "source": {"primitive": "cylinder", "radius": 2, "height": 5}},
    {"name": "ring", "type": "mesh", "source": {"primitive": "torus", "major_radius": 20,
                                                "minor_radius": 3, "segments": 8}},
    {"name": "sheet", "type": "mesh", "source": {"primitive": "quad", "size": 7}}
  )"));
  ASSERT_EQ(s.meshes.size(), 5u);
  const MeshObject& ball = s.meshes[0];
  EXPECT_EQ(ball.name, "ball");
  glm::dvec3 c = centroid(*ball.mesh);
  EXPECT_NEAR(c.x, 100.0, 1e-3);
  EXPECT_NEAR(c.y, 0.0, 1e-3);
  EXPECT_EQ(ball.material.color, glm::vec3(1, 0, 0));
  EXPECT_EQ(ball.material.opacity, 0.5f);
  EXPECT_TRUE(ball.material.shading.enabled);
  EXPECT_EQ(ball.material.shading.specular, 0.0f);
  EXPECT_EQ(ball.material.shading.shininess, 8.0f);
  EXPECT_EQ(ball.material.shading.ambient, Shading{}.ambient);
  EXPECT_EQ(ball.thickness, 2.0);
  EXPECT_EQ(s.meshes[1].thickness, std::nullopt);
  EXPECT_FALSE(s.meshes[1].material.shading.enabled);
  EXPECT_TRUE(s.meshes[2].material.shading.enabled);  // meshes are shaded by default
  EXPECT_NEAR(test::signed_volume(*s.meshes[1].mesh), 6.0, 1e-5);
  for (const glm::vec3& p : s.meshes[4].mesh->positions) EXPECT_FLOAT_EQ(std::abs(p.x), 3.5f);
  ASSERT_EQ(s.order.size(), 5u);
  EXPECT_EQ(s.order[3].kind, ObjectKind::mesh);
  EXPECT_EQ(s.order[3].index, 3);
}

TEST(ParseScene, TransformOrderIsScaleThenRotateXYZThenTranslate) {
  Scene s = parse(with_objects(R"(
    {"name": "q", "type": "mesh", "source": {"primitive": "quad", "size": [2, 2]},
     "transform": {"translate": [0, 0, 10], "rotate_deg": [90, 0, 90], "scale": [3, 1, 1]}}
  )"));
  // S: x in [-3, 3]; Rx(90): y -> z; Rz(90): x -> y; then +10 in z.
  for (const glm::vec3& p : s.meshes[0].mesh->positions) {
    EXPECT_NEAR(std::abs(p.y), 3.0f, 1e-5f);
    EXPECT_NEAR(std::abs(p.z - 10.0f), 1.0f, 1e-5f);
    EXPECT_NEAR(p.x, 0.0f, 1e-5f);
  }
  for (const glm::vec3& n : s.meshes[0].mesh->normals) EXPECT_NEAR(std::abs(n.x), 1.0f, 1e-5f);
}

TEST(ParseScene, MatrixTransformIsRowMajor) {
  Scene s = parse(with_objects(R"(
    {"name": "q", "type": "mesh", "source": {"primitive": "box", "size": 2},
     "transform": {"matrix": [[1, 0, 0, 5], [0, 1, 0, 6], [0, 0, 1, 7], [0, 0, 0, 1]]}}
  )"));
  glm::dvec3 c = centroid(*s.meshes[0].mesh);
  EXPECT_NEAR(c.x, 5.0, 1e-5);
  EXPECT_NEAR(c.y, 6.0, 1e-5);
  EXPECT_NEAR(c.z, 7.0, 1e-5);
}

TEST(ParseScene, PlaneWithoutVolume) {
  Scene s = parse(with_objects(kPlane));
  ASSERT_EQ(s.planes.size(), 1u);
  const PlaneObject& p = s.planes[0];
  EXPECT_EQ(p.center, glm::dvec3(0, 0, 5));
  EXPECT_EQ(p.normal, glm::dvec3(0, 0, 1));
  EXPECT_NEAR(glm::dot(p.up, p.normal), 0.0, 1e-12);
  EXPECT_NEAR(glm::length(p.up), 1.0, 1e-12);
  EXPECT_EQ(p.size, glm::dvec2(50, 50));
  EXPECT_EQ(p.volume, -1);
  EXPECT_EQ(s.order[0].kind, ObjectKind::plane);
}

TEST(ParseScene, PlaneUpIsMadePerpendicular) {
  Scene s = parse(with_objects(R"({"name": "p", "type": "plane", "center": [0, 0, 0],
    "normal": [0, 1, 0], "up": [0, 1, 1], "size": [10, 20], "window": [100, 50],
    "color": [0.5, 0.5, 1], "opacity": 0.25, "thickness": 0.5})"));
  const PlaneObject& p = s.planes[0];
  EXPECT_NEAR(p.up.z, 1.0, 1e-12);
  EXPECT_EQ(p.size, glm::dvec2(10, 20));
  EXPECT_EQ(p.window, glm::dvec2(100, 50));
  EXPECT_EQ(p.opacity, 0.25f);
  EXPECT_EQ(p.thickness, 0.5);
  EXPECT_NEAR(glm::dot(s.planes[0].up, s.planes[0].normal), 0.0, 1e-12);
}

TEST(ParseScene, DefaultPlaneUpIsPerpendicularForAnyNormal) {
  for (const char* n : {"[0, 0, 1]", "[0, 1, 0]", "[1, 0, 0]", "[1, 1, 1]", "[0, -1, 0.01]"}) {
    Scene s =
        parse(with_objects(R"({"name": "p", "type": "plane", "center": [0, 0, 0], "normal": )" +
                           std::string(n) + R"(, "size": 1})"));
    EXPECT_NEAR(glm::dot(s.planes[0].up, s.planes[0].normal), 0.0, 1e-12) << n;
    EXPECT_NEAR(glm::length(s.planes[0].up), 1.0, 1e-12) << n;
  }
}

// ---- files and volumes -----------------------------------------------------------------------

// A 4x5x6 volume with 2 mm voxels at origin (10, 20, 30).
VolumeData small_volume() {
  VolumeData v;
  v.dims = {4, 5, 6};
  std::vector<int16_t> voxels(v.voxel_count());
  for (size_t i = 0; i < voxels.size(); ++i) voxels[i] = static_cast<int16_t>(i);
  v.voxels = voxels;
  v.index_to_world = glm::dmat4(2.0);
  v.index_to_world[3] = glm::dvec4(10, 20, 30, 1);
  return v;
}

TEST(LoadScene, RelativePathsResolveAgainstTheSceneFolder) {
  test::TempDir dir;
  dir.write("meshes/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  std::filesystem::create_directories(dir.path() / "data");
  write_nrrd(small_volume(), dir.path() / "data" / "vol.nrrd");
  auto scene_file = dir.write("scenes/scene.json", R"({"objects": [
    {"name": "tri", "type": "mesh", "source": {"file": "../meshes/tri.obj"},
     "transform": {"scale": 10}},
    {"name": "v", "type": "volume", "source": {"file": "../data/vol.nrrd"},
     "transfer_function": {"points": [[0, 0, 0, 0, 0], [100, 1, 1, 1, 1]]}}
  ]})");
  Scene s = load_scene(scene_file);
  EXPECT_EQ(s.file, scene_file);
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].mesh->triangles.size(), 1u);
  EXPECT_FLOAT_EQ(s.meshes[0].mesh->positions[1].x, 10.0f);
  ASSERT_EQ(s.volumes.size(), 1u);
  EXPECT_EQ(s.volumes[0].data->dims, glm::ivec3(4, 5, 6));
  ASSERT_EQ(s.order.size(), 2u);
  EXPECT_EQ(s.order[0].kind, ObjectKind::mesh);
  EXPECT_EQ(s.order[1].kind, ObjectKind::volume);
  EXPECT_EQ(s.order[1].index, 0);
}

TEST(LoadScene, VolumeObjectsShareTheirSourceAndApplyTheTransform) {
  test::TempDir dir;
  write_nrrd(small_volume(), dir.path() / "vol.nrrd");
  auto scene_file = dir.write("scene.json", R"({"objects": [
    {"name": "a", "type": "volume", "source": {"file": "vol.nrrd"},
     "transfer_function": {"points": [[0, 0, 0, 0, 0], [50, 1, 0.5, 0, 0.25]], "unit_distance": 2},
     "shading": {"diffuse": 0.5}, "clip_planes": [{"point": [0, 0, 40], "normal": [0, 0, -3]}]},
    {"name": "b", "type": "volume", "source": {"file": "./vol.nrrd"}, "style": "iso",
     "iso_value": 60, "transform": {"translate": [1, 2, 3]}},
    {"name": "axial", "type": "plane", "volume": "b", "normal": [0, 0, 1]}
  ]})");
  Scene s = load_scene(scene_file);
  ASSERT_EQ(s.volumes.size(), 2u);
  const VolumeObject& a = s.volumes[0];
  const VolumeObject& b = s.volumes[1];
  EXPECT_EQ(a.data.get(), b.data.get());  // one copy for one source
  EXPECT_EQ(a.style, VolumeStyle::dvr);
  ASSERT_EQ(a.transfer_function.points.size(), 2u);
  EXPECT_EQ(a.transfer_function.points[1].value, 50.0);
  EXPECT_EQ(a.transfer_function.points[1].rgba, glm::vec4(1, srgb_decode(0.5f), 0, 0.25f));
  EXPECT_EQ(a.transfer_function.unit_distance, 2.0);
  EXPECT_TRUE(a.shading.enabled);
  EXPECT_EQ(a.shading.diffuse, 0.5f);
  ASSERT_EQ(a.clip_planes.size(), 1u);
  EXPECT_EQ(a.clip_planes[0].normal, glm::dvec3(0, 0, -1));
  EXPECT_EQ(glm::dvec3(a.index_to_world[3]), glm::dvec3(10, 20, 30));
  EXPECT_EQ(b.style, VolumeStyle::iso);
  EXPECT_EQ(b.iso_value, 60.0);
  EXPECT_FALSE(b.shading.enabled);  // volumes are unshaded without a "shading" block
  ASSERT_EQ(b.transfer_function.points.size(), 1u);
  EXPECT_EQ(b.transfer_function.points[0].rgba, glm::vec4(1.0f));
  EXPECT_EQ(glm::dvec3(b.index_to_world[3]), glm::dvec3(11, 22, 33));
  EXPECT_EQ(b.index_to_world[0][0], 2.0);
  // The plane defaults to the volume's centre and covers its bounding box.
  const PlaneObject& p = s.planes[0];
  EXPECT_EQ(p.volume, 1);
  // Voxel extent: index -0.5 .. dims - 0.5 at 2 mm, shifted by (11, 22, 33).
  EXPECT_NEAR(p.center.x, 11 + 3.0, 1e-9);
  EXPECT_NEAR(p.center.y, 22 + 4.0, 1e-9);
  EXPECT_NEAR(p.center.z, 33 + 5.0, 1e-9);
  double diagonal = std::sqrt(8.0 * 8.0 + 10.0 * 10.0 + 12.0 * 12.0);
  EXPECT_NEAR(p.size.x, diagonal, 1e-9);
  EXPECT_NEAR(p.size.y, diagonal, 1e-9);
}

TEST(LoadScene, SharedFlairVolumeLoads) {
  SKIP_WITHOUT_SHARED_DATA("FLAIR.nrrd");
  const std::filesystem::path flair = test::shared_data("FLAIR.nrrd");
  Scene s = parse(with_objects(R"({"name": "mr", "type": "volume", "source": {"file": ")" +
                               flair.string() +
                               R"("}, "transfer_function": {"points": [[0, 0, 0, 0, 0]]}})"));
  EXPECT_EQ(s.volumes[0].data->dims, glm::ivec3(124, 160, 140));
}

TEST(LoadScene, MissingSceneFileIsNamed) {
  std::string msg = error_of([] { load_scene("/nonexistent/scene.json"); });
  EXPECT_CONTAINS(msg, "/nonexistent/scene.json");
}

TEST(LoadScene, MissingMeshFileNamesTheResolvedPathAndJsonPath) {
  test::TempDir dir;
  auto scene_file =
      dir.write("scene.json",
                with_objects(R"({"name": "m", "type": "mesh", "source": {"file": "gone.stl"}})"));
  std::string msg = error_of([&] { load_scene(scene_file); });
  EXPECT_CONTAINS(msg, scene_file.string() + ": objects[0].source.file: no such file");
  EXPECT_CONTAINS(msg, (dir.path() / "gone.stl").string());
}

TEST(LoadScene, MissingVolumeFileNamesTheResolvedPath) {
  test::TempDir dir;
  auto scene_file = dir.write("scene.json", with_objects(R"({"name": "v", "type": "volume",
    "source": {"file": "ct.nrrd"}, "transfer_function": {"points": [[0, 0, 0, 0, 0]]}})"));
  std::string msg = error_of([&] { load_scene(scene_file); });
  EXPECT_CONTAINS(msg, "objects[0].source.file: no such file");
  EXPECT_CONTAINS(msg, (dir.path() / "ct.nrrd").string());
}

TEST(LoadScene, ReaderErrorsGetTheJsonPath) {
  test::TempDir dir;
  dir.write("junk.nrrd", "not a nrrd file\n");
  dir.write("junk.obj", "v 0 0 0\n");
  auto scene_file = dir.write("scene.json", with_objects(R"({"name": "v", "type": "volume",
    "source": {"file": "junk.nrrd"}, "transfer_function": {"points": [[0, 0, 0, 0, 0]]}})"));
  std::string msg = error_of([&] { load_scene(scene_file); });
  EXPECT_CONTAINS(msg, scene_file.string() + ": objects[0].source.file: ");
  EXPECT_CONTAINS(msg, "junk.nrrd");
  scene_file = dir.write("scene.json", with_objects(R"({"name": "m", "type": "mesh",
    "source": {"file": "junk.obj"}})"));
  msg = error_of([&] { load_scene(scene_file); });
  EXPECT_CONTAINS(msg, scene_file.string() + ": objects[0].source.file: ");
  EXPECT_CONTAINS(msg, "junk.obj");
}

// ---- overrides ------------------------------------------------------------------------------

TEST(ParseScene, OverridesByIndexAndByName) {
  std::string text = with_objects(kSphere + "," + kPlane);
  Scene s =
      parse(text, {"image.width=256", "objects.0.material.opacity=0.3", "objects.cut.opacity=0.6",
                   "objects[1].color=[0, 1, 0]", "render.spp=4", "render.method=peel"});
  EXPECT_EQ(s.image.width, 256);
  EXPECT_EQ(s.meshes[0].material.opacity, 0.3f);
  EXPECT_EQ(s.planes[0].opacity, 0.6f);
  EXPECT_EQ(s.planes[0].color, glm::vec3(0, 1, 0));
  EXPECT_EQ(s.render.spp, 4);
  EXPECT_EQ(s.render.method, "peel");
}

TEST(ParseScene, OverridesAreValidatedLikeTheFile) {
  std::string text = with_objects(kSphere);
  std::string msg = parse_error(text, {R"(objects.0.transform.translate=[1,2,"x"])"});
  EXPECT_CONTAINS(msg,
                  "scene.json: objects[0].transform.translate[2]: expected a number, got "
                  "string \"x\"");
  msg = parse_error(text, {"objects.ball.material.opacity=nan"});
  EXPECT_CONTAINS(msg, "objects[0].material.opacity: expected a number, got string \"nan\"");
  msg = parse_error(text, {"image.width=1e999"});
  EXPECT_CONTAINS(msg, "image.width: expected an integer, got string \"1e999\"");
  msg = parse_error(text, {"objects.bal.material.opacity=1"});
  EXPECT_CONTAINS(msg, "--set objects.bal.material.opacity=1");
  EXPECT_CONTAINS(msg, "did you mean 'ball'?");
  msg = parse_error(text, {"image.width=5", "image.width.x=1"});
  EXPECT_CONTAINS(msg, "scene.json: --set image.width.x=1:");
}

// ---- errors --------------------------------------------------------------------------------

TEST(ParseSceneErrors, MalformedJsonGivesLineAndColumn) {
  std::string msg = parse_error("{\n  \"objects\": [\n  ,]\n}");
  EXPECT_CONTAINS(msg, "scene.json: invalid JSON:");
  EXPECT_CONTAINS(msg, "line 3, column 3");
  EXPECT_CONTAINS(parse_error(""), "scene.json: invalid JSON");
  EXPECT_CONTAINS(parse_error("[1, 2]"), "scene.json: expected a JSON object at the top level");
}

TEST(ParseSceneErrors, UnknownKeysSuggestTheClosest) {
  std::string msg = parse_error(with_objects(
      R"({"name": "m", "type": "mesh", "source": {"primitive": "sphere", "radius": 1},
          "materal": {}})"));
  EXPECT_CONTAINS(msg, "scene.json: objects[0].materal: unknown key (did you mean 'material'?)");
  msg = parse_error(R"({"objects": [], "Camera": {}})");
  EXPECT_CONTAINS(msg, "Camera: unknown key (did you mean 'camera'?)");
  msg = parse_error(R"({"objects": [], "camera": {"fov": 30}})");
  EXPECT_CONTAINS(msg, "camera.fov: unknown key (known keys: eye, target");
  msg = parse_error(with_objects(
      R"({"name": "m", "type": "mesh", "source": {"primitive": "sphere", "radus": 1}})"));
  EXPECT_CONTAINS(msg, "objects[0].source.radus: unknown key (did you mean 'radius'?)");
  msg = parse_error(with_objects(
      R"({"name": "m", "type": "mesh", "source": {"primitive": "sphere", "radius": 1, "height": 2}})"));
  EXPECT_CONTAINS(msg, "objects[0].source.height: unknown key");
  msg = parse_error(with_objects(R"({"name": "m", "type": "mesh", "source": {"fiel": "a.obj"}})"));
  EXPECT_CONTAINS(msg, "objects[0].source.fiel: unknown key (did you mean 'file'?)");
}

TEST(ParseSceneErrors, UnknownChoicesSuggestTheClosest) {
  std::string msg = parse_error(with_objects(
      R"({"name": "m", "type": "mesh", "source": {"primitive": "spere", "radius": 1}})"));
  EXPECT_CONTAINS(msg,
                  "objects[0].source.primitive: \"spere\" is not one of sphere, box, "
                  "cylinder, torus, quad (did you mean 'sphere'?)");
  msg = parse_error(with_objects(R"({"name": "m", "type": "meshes"})"));
  EXPECT_CONTAINS(msg, "objects[0].type: \"meshes\" is not one of volume, mesh, plane");
  msg = parse_error(R"({"objects": [], "render": {"interpolation": "OVI"}})");
  EXPECT_CONTAINS(msg, "did you mean 'ovi'?");
}

TEST(ParseSceneErrors, WrongTypes) {
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "image": {"width": "abc"}})"),
                  "scene.json: image.width: expected an integer, got string \"abc\"");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "image": {"width": 10.5}})"),
                  "image.width: expected an integer, got number 10.5");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "camera": {"eye": [1, 2]}})"),
                  "camera.eye: expected an array of 3 numbers, got array [1,2]");
  EXPECT_CONTAINS(parse_error(R"({"objects": {}})"), "objects: expected an array, got object");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "camera": []})"),
                  "camera: expected an object, got array");
  EXPECT_CONTAINS(parse_error(with_objects(kSphere.substr(0, kSphere.size() - 1) +
                                           R"(, "thickness": "thick"})")),
                  "objects[0].thickness: expected a positive number of mm or \"auto\"");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"name": 3, "type": "mesh"})")),
                  "objects[0].name: expected a string, got number 3");
}

TEST(ParseSceneErrors, OutOfRangeValues) {
  std::string sphere_with = kSphere.substr(0, kSphere.size() - 1);
  EXPECT_CONTAINS(parse_error(with_objects(sphere_with + R"(, "material": {"opacity": 1.5}})")),
                  "scene.json: objects[0].material.opacity: 1.5 is not in [0, 1]");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "camera": {"fov_deg": 180}})"),
                  "camera.fov_deg: 180 is not in (0, 180)");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "image": {"height": 0}})"),
                  "image.height: 0 is not in [1, 16384]");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "image": {"background": [0, 0, 2]}})"),
                  "image.background[2]: 2 is not in [0, 1]");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "render": {"step_mm": -1}})"),
                  "render.step_mm: -1 is not in [1e-06, 1000000]");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "render": {"layers": 2}})"),
                  "render.layers: 2 is not in [4, 16]");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "lights": [{"intensity": -1}]})"),
                  "lights[0].intensity: -1 is not in [0, 1000]");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"name": "t", "type": "mesh", "source":
      {"primitive": "torus", "major_radius": 2, "minor_radius": 3}})")),
                  "objects[0].source.minor_radius: 3 must be less than major_radius 2");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"name": "s", "type": "mesh", "source":
      {"primitive": "sphere", "radius": 1, "segments": 2}})")),
                  "objects[0].source.segments: 2 is not in [3, 1024]");
}

TEST(ParseSceneErrors, SppMustBeAPerfectSquare) {
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "render": {"spp": 8}})"),
                  "render.spp: 8 is not a perfect square");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "render": {"spp": 0}})"), "render.spp: 0");
  EXPECT_EQ(parse(R"({"objects": [], "render": {"spp": 1}})").render.spp, 1);
  EXPECT_EQ(parse(R"({"objects": [], "render": {"spp": 64}})").render.spp, 64);
}

TEST(ParseSceneErrors, GeometricInconsistencies) {
  EXPECT_CONTAINS(
      parse_error(R"({"objects": [], "camera": {"eye": [0, 0, 0], "target": [0, 0, 0]}})"),
      "camera: eye and target are the same point");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "camera": {"eye": [0, 0, 9], "up": [0, 0, 1]}})"),
                  "camera: up [0, 0, 1] is parallel to the view direction");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "camera": {"up": [0, 0, 0]}})"),
                  "camera.up: [0,0,0] is not a usable direction");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "lights": [{"direction": [0, 0, 1]}]})"),
                  "lights[0].direction: only directional lights have a direction");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "lights": [{"type": "directional"}]})"),
                  "lights[0]: missing required key 'direction'");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"name": "p", "type": "plane", "center": [0, 0, 0],
      "normal": [0, 0, 1], "up": [0, 0, -2], "size": 1})")),
                  "objects[0].up: [0,0,-2] is parallel to the normal");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"name": "p", "type": "plane", "center": [0, 0, 0],
      "normal": [0, 0, 1]})")),
                  "objects[0]: missing required key 'size'");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"name": "p", "type": "plane", "center": [0, 0, 0],
      "normal": [0, 0, 1], "size": 1, "window": [40, 0]})")),
                  "objects[0].window[1]: window width 0 must be > 0");
}

TEST(ParseSceneErrors, TransformsMustBeFiniteAndInvertible) {
  std::string sphere_with = kSphere.substr(0, kSphere.size() - 1);
  EXPECT_CONTAINS(parse_error(with_objects(sphere_with + R"(, "transform": {"matrix":
          [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1]]}})")),
                  "scene.json: objects[0].transform: transform is singular");
  EXPECT_CONTAINS(parse_error(with_objects(sphere_with + R"(, "transform": {"scale": 0}})")),
                  "objects[0].transform: transform is singular");
  EXPECT_CONTAINS(parse_error(with_objects(sphere_with + R"(, "transform": {"matrix":
          [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]}})")),
                  "objects[0].transform.matrix[3]: the last row must be [0, 0, 0, 1]");
  EXPECT_CONTAINS(
      parse_error(with_objects(sphere_with + R"(, "transform": {"matrix": [[1, 0, 0, 0]]}})")),
      "objects[0].transform.matrix: expected 4 rows of 4 numbers");
  EXPECT_CONTAINS(
      parse_error(with_objects(sphere_with + R"(, "transform": {"matrix": [], "scale": 2}})")),
      "objects[0].transform: give either \"matrix\" or translate");
  EXPECT_CONTAINS(parse_error(with_objects(sphere_with + R"(, "transform": {"scale": "big"}})")),
                  "objects[0].transform.scale: expected a number or an array of 3 numbers");
  // A value too large for a double is a string after --set, so a type error, not infinity.
  EXPECT_CONTAINS(parse_error(with_objects(kSphere), {"objects.0.transform.scale=1e400"}),
                  "objects[0].transform.scale: expected a number or an array of 3 numbers, got "
                  "string \"1e400\"");
  // Entries finite as doubles but not as floats are refused where they stand.
  EXPECT_CONTAINS(parse_error(with_objects(sphere_with +
                                           R"(, "transform": {"scale": [1e300, 1e300, 1e300]}})")),
                  "objects[0].transform.scale[0]: 1e+300 is too large");
}

TEST(ParseSceneErrors, NamesMustBeUniqueAndUsable) {
  EXPECT_CONTAINS(parse_error(with_objects(kSphere + "," + kSphere)),
                  "scene.json: objects[1].name: \"ball\" is already the name of objects[0]");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"name": "", "type": "mesh"})")),
                  "objects[0].name: the name is empty");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"name": "a.b", "type": "mesh"})")),
                  "objects[0].name: \"a.b\" may not contain '.'");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"name": "12", "type": "mesh"})")),
                  "objects[0].name: \"12\" is all digits");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"type": "mesh"})")),
                  "objects[0]: missing required key 'name'");
  EXPECT_CONTAINS(parse_error(R"({"camera": {}})"), "scene.json: missing required key 'objects'");
}

TEST(ParseSceneErrors, PlaneVolumeMustNameAVolume) {
  test::TempDir dir;
  write_nrrd(small_volume(), dir.path() / "ct.nrrd");
  std::string text = with_objects(R"(
    {"name": "ct", "type": "volume", "source": {"file": "ct.nrrd"},
     "transfer_function": {"points": [[0, 0, 0, 0, 0]]}},
    )" + kSphere + R"(,
    {"name": "axial", "type": "plane", "volume": "ctt", "normal": [0, 0, 1]})");
  auto file = dir.write("scene.json", text);
  std::string msg = error_of([&] { load_scene(file); });
  EXPECT_CONTAINS(msg, file.string() +
                           ": objects[2].volume: no volume named 'ctt' (did you mean "
                           "'ct'?)");
  msg = error_of([&] { load_scene(file, {"objects.axial.volume=ball"}); });
  EXPECT_CONTAINS(msg, "objects[2].volume: 'ball' is a mesh, not a volume");
  Scene s = load_scene(file, {"objects.axial.volume=ct"});
  EXPECT_EQ(s.planes[0].volume, 0);
}

// Two phantom volumes and a mesh, for the zSlab settings that name objects.
std::string zslab_scene(const std::string& render) {
  return R"({"render": )" + render + R"(, "objects": [
    {"name": "cube", "type": "volume", "source": {"phantom": "cube", "size": 8},
     "transfer_function": {"points": [[0, 1, 1, 1, 0.5]]}},
    {"name": "ellipsoid", "type": "volume", "source": {"phantom": "ellipsoid", "size": 8},
     "transfer_function": {"points": [[0, 1, 1, 1, 0.5]]}},
    )" + kSphere +
         "]}";
}

TEST(ParseScene, ZslabLastVolumeAndOverflow) {
  Scene s = parse(zslab_scene("{}"));
  EXPECT_EQ(s.render.last_volume, "");  // automatic choice
  EXPECT_EQ(s.render.overflow, "greedy");
  s = parse(zslab_scene(R"({"last_volume": "cube", "overflow": "tail"})"));
  EXPECT_EQ(s.render.last_volume, "cube");
  EXPECT_EQ(s.render.overflow, "tail");
  s = parse(zslab_scene("{}"), {"render.last_volume=ellipsoid", "render.overflow=greedy"});
  EXPECT_EQ(s.render.last_volume, "ellipsoid");
  EXPECT_EQ(s.render.overflow, "greedy");
}

TEST(ParseSceneErrors, LastVolumeMustNameAVolume) {
  EXPECT_CONTAINS(parse_error(zslab_scene(R"({"last_volume": "elipsoid"})")),
                  "scene.json: render.last_volume: no volume named 'elipsoid' (did you mean "
                  "'ellipsoid'?)");
  EXPECT_CONTAINS(parse_error(zslab_scene("{}"), {"render.last_volume=nothing"}),
                  "render.last_volume: no volume named 'nothing'");
  EXPECT_CONTAINS(parse_error(zslab_scene(R"({"last_volume": "ball"})")),
                  "render.last_volume: 'ball' is a mesh, not a volume");
  EXPECT_CONTAINS(parse_error(R"({"render": {"last_volume": "ct"}, "objects": []})"),
                  "render.last_volume: no volume named 'ct'");
  EXPECT_CONTAINS(parse_error(zslab_scene(R"({"last_volume": 3})")),
                  "render.last_volume: expected a string");
}

TEST(ParseSceneErrors, OverflowIsGreedyOrTail) {
  EXPECT_CONTAINS(parse_error(zslab_scene(R"({"overflow": "tale"})")),
                  "render.overflow: \"tale\" is not one of greedy, tail (did you mean 'tail'?)");
  EXPECT_CONTAINS(parse_error(zslab_scene(R"({"peel_rest": "sorted"})")),
                  "render.peel_rest: \"sorted\" is not one of lost, unsorted");
}

TEST(ParseSceneErrors, TubeCoverageIsAutoOnOrOff) {
  EXPECT_CONTAINS(parse_error(zslab_scene(R"({"tube_coverage": "yes"})")),
                  "render.tube_coverage: \"yes\" is not one of auto, on, off");
  EXPECT_CONTAINS(parse_error(zslab_scene(R"({"tube_coverage": true})")),
                  "render.tube_coverage: expected a string");
  EXPECT_EQ(parse_scene(R"({"objects": []})", ".", "test").render.tube_coverage, "auto");
  EXPECT_EQ(parse_scene(R"({"render": {"tube_coverage": "off"}, "objects": []})", ".", "test")
                .render.tube_coverage,
            "off");
}

TEST(ParseSceneErrors, VolumeSettings) {
  test::TempDir dir;
  write_nrrd(small_volume(), dir.path() / "ct.nrrd");
  auto file = dir.write("scene.json", with_objects(R"(
    {"name": "ct", "type": "volume", "source": {"file": "ct.nrrd"},
     "transfer_function": {"points": [[0, 0, 0, 0, 0], [100, 1, 1, 1, 1]]}})"));
  auto error = [&](const std::string& assignment) {
    return error_of([&] { load_scene(file, {assignment}); });
  };
  EXPECT_CONTAINS(error("objects.ct.transfer_function.points=[[5, 0, 0, 0, 0], [1, 1, 1, 1, 1]]"),
                  "objects[0].transfer_function.points[1][0]: value 1 is below the previous "
                  "point's 5");
  EXPECT_CONTAINS(error("objects.ct.transfer_function.points=[[5, 0, 0, 0, 2]]"),
                  "objects[0].transfer_function.points[0][4]: 2 is not in [0, 1]");
  EXPECT_CONTAINS(error("objects.ct.transfer_function.points=[[5, 0, 0, 0]]"),
                  "objects[0].transfer_function.points[0]: expected a point [value, r, g, b, a]");
  EXPECT_CONTAINS(error("objects.ct.transfer_function.points=[]"),
                  "objects[0].transfer_function.points: needs at least one point");
  EXPECT_CONTAINS(error("objects.ct.transfer_function.unit_distance=0"),
                  "objects[0].transfer_function.unit_distance: 0 is not in [1e-06, 1000000]");
  EXPECT_CONTAINS(error("objects.ct.style=iso"), "objects[0]: missing required key 'iso_value'");
  EXPECT_CONTAINS(error("objects.ct.style=surface"), "objects[0].style: \"surface\" is not one of");
  EXPECT_CONTAINS(error("objects.ct.source.size=64"), "objects[0].source.size: only phantoms");
  EXPECT_CONTAINS(error("objects.ct.source.phantom=x"),
                  "objects[0].source: give either \"phantom\" or \"file\"");
  EXPECT_CONTAINS(error("objects.ct.clip_planes=[{\"point\": [0, 0, 0]}]"),
                  "objects[0].clip_planes[0]: missing required key 'normal'");
  EXPECT_CONTAINS(error("objects.ct.shading.ambiant=1"),
                  "objects[0].shading.ambiant: unknown key (did you mean 'ambient'?)");
  EXPECT_EQ(load_scene(file, {"objects.ct.style=mip"}).volumes[0].style, VolumeStyle::mip);
  std::string msg = error_of([&] {
    load_scene(file, {"objects.ct.transfer_function={}", "objects.ct.style=xray"});
  });
  EXPECT_CONTAINS(msg, "objects[0].transfer_function: missing required key 'points'");
  msg = error_of([&] {
    Scene s = load_scene(file);
    (void)s;
    load_scene(file, {"objects.0.transfer_function=null"});
  });
  EXPECT_CONTAINS(msg, "objects[0].transfer_function: expected an object, got null");
}

TEST(LoadScene, AFifoIsRefusedUnopenedAsSceneAndAsVolumeSource) {
  test::TempDir dir;
  const std::filesystem::path scene = dir.path() / "pipe.json";
  ASSERT_EQ(::mkfifo(scene.c_str(), 0600), 0);
  EXPECT_CONTAINS(error_of([&] { load_scene(scene); }), "pipe.json: is a FIFO (named pipe)");
  ASSERT_EQ(::mkfifo((dir.path() / "ct.nrrd").c_str(), 0600), 0);
  const std::filesystem::path file =
      dir.write("s.json",
                R"({"objects": [{"name": "ct", "type": "volume", "source": {"file": "ct.nrrd"},
                   "transfer_function": {"points": [[0, 1, 1, 1, 1]]}}]})");
  EXPECT_CONTAINS(error_of([&] { load_scene(file); }), "objects[0].source.file");
  EXPECT_CONTAINS(error_of([&] { load_scene(file); }), "is a FIFO");
}

TEST(ParseSceneErrors, ADuplicateKeyIsAnErrorNamingWhereItIs) {
  EXPECT_CONTAINS(parse_error(R"({"image": {"width": 64, "width": 32}})"),
                  "scene.json: image: key 'width' appears twice in the same object");
  EXPECT_CONTAINS(
      parse_error(R"({"objects": [{"name": "a", "type": "mesh"}, {"name": "b", "name": "c"}]})"),
      "scene.json: objects[1]: key 'name' appears twice");
  EXPECT_CONTAINS(parse_error(R"({"render": {}, "render": {}})"),
                  "scene.json: key 'render' appears twice");
  // The same key in different objects is fine.
  EXPECT_NO_THROW(
      parse(R"({"image": {"width": 8}, "camera": {"eye": [0, -1, 0]}, "objects": []})"));
}

TEST(ParseSceneErrors, DeepNestingIsAnErrorNotAStackOverflow) {
  for (int depth : {100000, 2000}) {
    const std::string deep = std::string(depth, '[') + std::string(depth, ']');
    EXPECT_CONTAINS(parse_error(R"({"description": )" + deep + "}"),
                    "scene.json: JSON nested deeper than 1024 levels");
    EXPECT_CONTAINS(parse_error("{}", {"image.width=" + deep}), "nested deeper than 1024");
  }
  EXPECT_CONTAINS(parse_error("{}", {R"(image={"width": 8, "width": 9})"}),
                  "--set image: key 'width' appears twice");
}

TEST(ParseSceneErrors, NumbersTooLargeForAFloatAreRefusedWithTheirPath) {
  const std::string volume =
      R"({"objects": [{"name": "ct", "type": "volume", "source": {"phantom": "cube", "size": 8},
          "transfer_function": {"points": [[1e300, 1, 1, 1, 1]]}}]})";
  EXPECT_CONTAINS(parse_error(volume),
                  "objects[0].transfer_function.points[0][0]: 1e+300 is too large");
  EXPECT_CONTAINS(parse_error(R"({"camera": {"eye": [0, -1e308, 0]}, "objects": []})"),
                  "camera.eye[1]: -1e+308 is too large: numbers are used as floats");
  EXPECT_CONTAINS(parse_error(R"({"objects": []})", {"camera.ortho_height=1e308"}),
                  "camera.ortho_height: 1e+308 is too large");
}

TEST(ParseSceneErrors, GeometryOutsideTheLimitsIsRefusedWithItsPath) {
  // Finite as floats, but their squares and products would not be.
  EXPECT_CONTAINS(parse_error(R"({"camera": {"eye": [0, -1e30, 0]}, "objects": []})"),
                  "camera.eye[1]: -1e+30 is not in [-1000000, 1000000]");
  EXPECT_CONTAINS(parse_error(R"({"objects": []})", {"camera.ortho_height=1e30"}),
                  "camera.ortho_height: 1e+30 is not in [1e-06, 1000000]");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"name": "b", "type": "mesh", "source":
      {"primitive": "sphere", "radius": 1e-30}})")),
                  "objects[0].source.radius: 1e-30 is not in [1e-06, 1000000]");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"name": "b", "type": "mesh", "source":
      {"primitive": "sphere", "radius": 1}, "transform": {"scale": 1e20}})")),
                  "objects[0].transform: transform stretches axis x by 1e+20");
  EXPECT_CONTAINS(parse_error(with_objects(R"({"name": "b", "type": "mesh", "source":
      {"primitive": "sphere", "radius": 1}, "transform": {"matrix":
      [[1, 0, 0, 0], [0, 1, 0, 5e9], [0, 0, 1, 0], [0, 0, 0, 1]]}})")),
                  "transform moves y by 5e+09 mm");
  EXPECT_CONTAINS(parse_error(R"({"objects": [], "lights": [{"intensity": 1e30}]})"),
                  "lights[0].intensity: 1e+30 is not in [0, 1000]");
  EXPECT_NO_THROW(parse(R"({"camera": {"eye": [0, -1e6, 0]}, "objects": []})"));
}

}  // namespace
}  // namespace imx
