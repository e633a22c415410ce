// ViewerState: every edit kind changes the image and the saved scene file renders the same bytes
// as the session; bad messages get one clear error and change nothing; data keeps its identity.
#include "server/viewer_state.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "presets/window_presets.hpp"
#include "same_image.hpp"
#include "scene_fixture.hpp"
#include "server/reading_views.hpp"
#include "temp_dir.hpp"

namespace imx::server {
namespace {

using test::error_of;
using test::TempDir;

using Json = nlohmann::json;

constexpr int kSize = 40;

// An example at kSize pixels with its phantoms at `phantom` voxels, so that tests stay fast.
ViewerState small(const std::string& name, const std::vector<std::string>& volumes,
                  int phantom = 48) {
  return load_viewer_state(test::example_scene(name),
                           test::small_example_overrides(kSize, volumes, phantom));
}

Image draw(const Scene& scene) {
  RenderOptions options;
  options.method = "zslab";
  options.spp = 1;
  return render(scene, options);
}

using test::same_bytes;

// Applies `message`, then checks that the image changed and that the saved file renders the
// session's bytes exactly.
void expect_edit_round_trips(ViewerState& state, const Json& message) {
  SCOPED_TRACE(message.dump());
  const Image before = draw(state.scene());
  EXPECT_TRUE(apply_edit(state, message));
  const Image after = draw(state.scene());
  EXPECT_FALSE(same_bytes(before, after)) << "the edit changed nothing";
  TempDir dir;
  const std::filesystem::path saved = dir.write("saved.json", state.document.text());
  const Scene reloaded = load_scene(saved);
  EXPECT_TRUE(same_bytes(after, draw(reloaded))) << state.document.text();
}

Json edit(const std::string& object, Json fields) {
  fields["type"] = "edit";
  fields["seq"] = 1;
  fields["moving"] = false;
  fields["object"] = object;
  return fields;
}

TEST(ViewerState, LoadsTheSceneAndItsDocument) {
  ViewerState s = small("ct-implant", {"ct"});
  ASSERT_EQ(s.scene().order.size(), 4u);
  EXPECT_EQ(s.visible, std::vector<bool>(4, true));
  EXPECT_EQ(s.opacity, (std::vector<float>{1.0f, 0.5f, 0.5f, 0.6f}));
  ASSERT_EQ(s.transfer_functions.size(), 1u);
  EXPECT_EQ(s.transfer_functions[0].points.size(), 4u);
  EXPECT_EQ(s.document.json()["image"]["width"], kSize);  // overrides are in the document
  EXPECT_EQ(s.document.json()["objects"][0]["source"]["size"], 48);
  EXPECT_EQ(s.initial_camera.eye, s.scene().camera.eye);
  // Saved untouched, the file renders as the session does.
  TempDir dir;
  EXPECT_TRUE(
      same_bytes(draw(s.scene()), draw(load_scene(dir.write("s.json", s.document.text())))));
}

TEST(ViewerState, CameraEditRoundTrips) {
  ViewerState s = small("ct-implant", {"ct"});
  s.document.set("camera.projection=perspective");
  expect_edit_round_trips(s, {{"type", "camera"},
                              {"seq", 3},
                              {"moving", true},
                              {"eye", {300, -400, 100}},
                              {"target", {0, 0, 20}},
                              {"up", {0, 0, 2}},
                              {"fov_deg", 25}});
  EXPECT_EQ(s.document.json()["camera"]["projection"], "perspective");  // other keys stay
  EXPECT_EQ(s.scene().camera.up, glm::dvec3(0, 0, 1));
  EXPECT_EQ(s.scene().camera.fov_deg, 25.0);
  EXPECT_NE(s.initial_camera.eye, s.scene().camera.eye);
  // The same camera again changes nothing.
  EXPECT_FALSE(apply_edit(s, {{"type", "camera"}, {"eye", {300, -400, 100}}}));
}

// Cameras as a page moves them (camera.js): orbit about the target's vertical, zoom.
Json camera_json(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up) {
  return {{"eye", {eye.x, eye.y, eye.z}},
          {"target", {target.x, target.y, target.z}},
          {"up", {up.x, up.y, up.z}},
          {"fov_deg", 30.0}};
}
struct PageCamera {
  glm::dvec3 eye, target, up;
  Json json() const { return camera_json(eye, target, up); }
  void orbit(double radians) {
    const glm::dvec3 axis = glm::normalize(up);
    const glm::dvec3 off = eye - target;
    eye = target + off * std::cos(radians) + glm::cross(axis, off) * std::sin(radians) +
          axis * glm::dot(axis, off) * (1.0 - std::cos(radians));
  }
  void zoom(double factor) { eye = target + (eye - target) * factor; }
};
PageCamera page_camera(const Camera& c) {
  return {c.eye, c.target, c.up};
}
// A move message: the camera the page moved (`from`) and where it went.
Json move(const PageCamera& from, const PageCamera& to) {
  Json m = to.json();
  m["type"] = "camera";
  m["from"] = from.json();
  return m;
}

// Two windows move the camera at once, each from the camera it last saw: window A orbits, window
// B (which has not seen A's orbit) zooms. In any interleaving both moves count: the camera ends
// looking where A turned it, at the distance B's zooms give, and the saved file agrees.
TEST(ViewerState, MovesFromTwoWindowsComposeInEveryOrder) {
  const ViewerState start = small("ct-implant", {"ct"});
  std::mt19937 random(7);
  for (int trial = 0; trial < 50; ++trial) {
    ViewerState s = start;
    PageCamera a = page_camera(s.scene().camera), b = a;
    const double distance0 = glm::length(a.eye - a.target);
    double turned = 0.0, zoomed = 1.0;
    std::vector<char> order(6, 'a');
    std::fill(order.begin() + 3, order.end(), 'b');
    std::shuffle(order.begin(), order.end(), random);
    for (char who : order) {
      if (who == 'a') {
        const PageCamera before = a;
        const double angle = std::uniform_real_distribution<double>(0.1, 0.7)(random);
        a.orbit(angle);
        turned += angle;
        apply_edit(s, move(before, a));
      } else {
        const PageCamera before = b;
        const double factor = std::uniform_real_distribution<double>(0.6, 0.95)(random);
        b.zoom(factor);
        zoomed *= factor;
        apply_edit(s, move(before, b));
      }
    }
    const Camera& c = s.scene().camera;
    PageCamera want = page_camera(start.scene().camera);
    want.orbit(turned);
    const glm::dvec3 direction = glm::normalize(c.eye - c.target);
    EXPECT_LT(glm::length(direction - glm::normalize(want.eye - want.target)), 1e-9)
        << "A's orbit was undone (trial " << trial << ")";
    EXPECT_NEAR(glm::length(c.eye - c.target), distance0 * zoomed, 1e-6 * distance0)
        << "B's zoom was lost (trial " << trial << ")";
    EXPECT_LT(glm::length(c.target - want.target), 1e-9);
    const Scene reloaded = load_scene(TempDir().write("s.json", s.document.text()));
    EXPECT_LT(glm::length(reloaded.camera.eye - c.eye), 1e-9);
  }
  // Without `from` a camera is set as sent: reset view and the snap buttons.
  ViewerState s = start;
  PageCamera set = page_camera(s.scene().camera);
  set.orbit(1.0);
  Json absolute = set.json();
  absolute["type"] = "camera";
  EXPECT_TRUE(apply_edit(s, absolute));
  EXPECT_EQ(s.scene().camera.eye, set.eye);
  // A move whose `from` is not a camera is refused, changing nothing.
  Json bad = move(set, set);
  bad["from"]["eye"] = bad["from"]["target"];
  EXPECT_CONTAINS(error_of([&] { apply_edit(s, bad); }), "from");
  EXPECT_EQ(s.scene().camera.eye, set.eye);
}

TEST(ViewerState, MeshVisibilityAndOpacityRoundTrip) {
  ViewerState s = small("ct-implant", {"ct"});
  expect_edit_round_trips(s, edit("screw-left", {{"visible", false}}));
  EXPECT_EQ(s.scene().meshes[0].material.opacity, 0.0f);
  EXPECT_FALSE(s.visible[1]);
  EXPECT_EQ(s.opacity[1], 0.5f);  // the user's opacity is kept while hidden
  EXPECT_EQ(s.document.json()["objects"][1]["visible"], false);
  expect_edit_round_trips(s, edit("plate", {{"opacity", 0.95}}));
  EXPECT_EQ(s.scene().meshes[2].material.opacity, 0.95f);
  EXPECT_EQ(s.document.json()["objects"][3]["material"]["opacity"], 0.95);
  // Opacity of a hidden mesh: kept, not shown; showing it again uses it.
  EXPECT_FALSE(apply_edit(s, edit("screw-left", {{"opacity", 0.5}})));
  EXPECT_EQ(s.scene().meshes[0].material.opacity, 0.0f);
  expect_edit_round_trips(s, edit("screw-left", {{"visible", true}, {"opacity", 0.9}}));
  EXPECT_EQ(s.scene().meshes[0].material.opacity, 0.9f);
  EXPECT_FALSE(s.document.json()["objects"][1].contains("visible"));
}

TEST(ViewerState, VolumeOpacityAndVisibilityRoundTrip) {
  ViewerState s = small("fusion", {"ct", "pet"});
  expect_edit_round_trips(s, edit("ct", {{"opacity", 0.3}}));
  const TransferFunction& user = s.transfer_functions[0];
  const TransferFunction& shown = s.scene().volumes[0].transfer_function;
  ASSERT_EQ(user.points.size(), shown.points.size());
  EXPECT_EQ(user.points[5].rgba.a, 0.06f);  // the user's TF is unscaled
  EXPECT_FLOAT_EQ(shown.points[5].rgba.a, 0.06f * 0.3f);
  expect_edit_round_trips(s, edit("pet", {{"visible", false}}));
  for (const TfPoint& p : s.scene().volumes[1].transfer_function.points) EXPECT_EQ(p.rgba.a, 0.0f);
  expect_edit_round_trips(s, edit("pet", {{"visible", true}}));
  EXPECT_EQ(s.scene().volumes[1].transfer_function.points[4].rgba.a, 0.9f);
}

TEST(ViewerState, TransferFunctionEditRoundTrips) {
  ViewerState s = small("fusion", {"ct", "pet"});
  s.document.set("objects.1.transfer_function.unit_distance=1.0");
  expect_edit_round_trips(
      s, edit("pet", {{"transfer_function", {{0, 0, 0, 0, 0}, {3, 0, 1, 0, 0.5}, {12, 0, 1, 1, 1}}},
                      {"opacity", 0.8}}));
  EXPECT_EQ(s.transfer_functions[1].points.size(), 3u);
  EXPECT_EQ(s.transfer_functions[1].points[1].rgba.a, 0.5f);
  const Json& tf = s.document.json()["objects"][1]["transfer_function"];
  EXPECT_EQ(tf["points"][1][4], 0.4);  // scaled by the opacity, written tidily
  EXPECT_EQ(tf["unit_distance"], 1.0);
}

TEST(ViewerState, PresetBecomesPointsWithItsShading) {
  TempDir dir;
  const std::filesystem::path file = dir.write("preset.json", R"({
    "camera": {"eye": [0, -500, 0], "target": [0, 0, 0], "up": [0, 0, 1]},
    "image": {"width": 40, "height": 40},
    "objects": [{"name": "head", "type": "volume", "source": {"phantom": "ct-head", "size": 48},
                 "transfer_function": {"preset": "ct-bone", "shift": 50}}]})");
  ViewerState s = load_viewer_state(file);
  ASSERT_TRUE(s.scene().volumes[0].shading.enabled);  // the preset's shading
  expect_edit_round_trips(s, edit("head", {{"opacity", 0.5}}));
  const Json& object = s.document.json()["objects"][0];
  EXPECT_TRUE(object["transfer_function"].contains("points"));
  EXPECT_FALSE(object["transfer_function"].contains("preset"));
  EXPECT_EQ(object["shading"]["enabled"], true);
}

TEST(ViewerState, PlaneEditsRoundTrip) {
  ViewerState s = small("mpr", {"ct"});
  expect_edit_round_trips(s, edit("axial", {{"window", {300, 900}}}));
  EXPECT_EQ(s.scene().planes[0].window, glm::dvec2(300, 900));
  expect_edit_round_trips(s, edit("axial", {{"center", {0, 0, 40}}}));
  EXPECT_EQ(s.scene().planes[0].center, glm::dvec3(0, 0, 40));
  expect_edit_round_trips(s, edit("coronal", {{"opacity", 0.9}}));
  EXPECT_EQ(s.scene().planes[1].opacity, 0.9f);
  expect_edit_round_trips(s, edit("sagittal", {{"visible", false}}));
  EXPECT_EQ(s.scene().planes[2].opacity, 0.0f);
  EXPECT_EQ(s.opacity[3], 1.0f);
}

TEST(ViewerState, ClipPlanesEditRoundTrips) {
  ViewerState s = small("mpr", {"ct"});
  expect_edit_round_trips(
      s,
      edit("ct", {{"clip_planes", Json::array({{{"point", {0, 0, 0}}, {"normal", {0, 2, 0}}}})}}));
  ASSERT_EQ(s.scene().volumes[0].clip_planes.size(), 1u);
  EXPECT_EQ(s.scene().volumes[0].clip_planes[0].normal, glm::dvec3(0, 1, 0));
  expect_edit_round_trips(s, edit("ct", {{"clip_planes", Json::array()}}));
  EXPECT_TRUE(s.scene().volumes[0].clip_planes.empty());
}

TEST(ViewerState, DataKeepsItsIdentityAcrossEdits) {
  ViewerState s = small("ct-implant", {"ct"});
  const auto volume = s.scene().volumes[0].data;
  const auto mesh = s.scene().meshes[1].mesh;
  apply_edit(s, edit("ct", {{"opacity", 0.5}, {"visible", false}}));
  apply_edit(s, edit("ct", {{"transfer_function", {{0, 1, 1, 1, 0}, {900, 1, 1, 1, 1}}}}));
  apply_edit(s, edit("screw-right", {{"opacity", 0.1}}));
  EXPECT_EQ(s.scene().volumes[0].data.get(), volume.get());
  EXPECT_EQ(s.scene().meshes[1].mesh.get(), mesh.get());
}

TEST(ViewerState, HiddenInTheFileKeepsTheUsersValues) {
  TempDir dir;
  const std::filesystem::path file = dir.write("hidden.json", R"({
    "image": {"width": 40, "height": 40},
    "objects": [
      {"name": "v", "type": "volume", "source": {"phantom": "ct-head", "size": 32}, "visible": false,
       "transfer_function": {"points": [[0, 1, 1, 1, 0], [500, 1, 1, 1, 0.5]]}},
      {"name": "m", "type": "mesh", "source": {"primitive": "sphere", "radius": 20},
       "material": {"opacity": 0.7}, "visible": false},
      {"name": "p", "type": "plane", "volume": "v", "normal": [0, 0, 1], "opacity": 0.4,
       "visible": false}]})");
  ViewerState s = load_viewer_state(file);
  EXPECT_EQ(s.visible, std::vector<bool>(3, false));
  EXPECT_EQ(s.opacity, (std::vector<float>{1.0f, 0.7f, 0.4f}));
  EXPECT_EQ(s.transfer_functions[0].points[1].rgba.a, 0.5f);
  EXPECT_EQ(s.scene().volumes[0].transfer_function.points[1].rgba.a, 0.0f);
  apply_edit(s, edit("v", {{"visible", true}}));
  apply_edit(s, edit("m", {{"visible", true}}));
  apply_edit(s, edit("p", {{"visible", true}}));
  EXPECT_EQ(s.scene().volumes[0].transfer_function.points[1].rgba.a, 0.5f);
  EXPECT_EQ(s.scene().meshes[0].material.opacity, 0.7f);
  EXPECT_EQ(s.scene().planes[0].opacity, 0.4f);
}

TEST(ViewerState, BadMessagesChangeNothing) {
  ViewerState s = small("mpr", {"ct"}, 24);
  const Json document = s.document.json();
  const Image image = draw(s.scene());
  const struct {
    Json message;
    const char* says;
  } cases[] = {
      {Json::array(), "expected a JSON object, got array"},
      {{{"seq", 1}}, "missing required key 'type'"},
      {{{"type", "settings"}, {"method", "mdvr"}}, "\"settings\" is not an edit"},
      {{{"type", "camera"}, {"eye", {0, 0, 0}}, {"target", {0, 0, 0}}}, "the same point"},
      {{{"type", "camera"}, {"up", {-380, -440, 300}}}, "parallel to the view direction"},
      {{{"type", "camera"}, {"fov_deg", 180}}, "camera: fov_deg: 180 is not in (0, 180)"},
      {{{"type", "camera"}, {"eye", {0, 0, "x"}}}, "camera: eye[2]: expected a number"},
      {{{"type", "camera"}, {"eye", {0, 0, 1e300}}}, "camera: eye[2]"},
      {{{"type", "camera"}, {"fov", 20}}, "camera: fov: unknown key"},
      {edit("axail", {{"opacity", 0.5}}),
       "\"axail\" is not an object of the scene (did you mean "
       "'axial'?); they are: ct, axial, coronal, sagittal"},
      {edit("ct", {{"opacity", 1.5}}), "edit of 'ct': opacity: 1.5 is not in [0, 1]"},
      {edit("ct", {{"visible", 1}}), "edit of 'ct': visible: expected true or false"},
      {edit("ct", {{"opacity", 0.5}, {"window", {1, -2}}}),
       "edit of 'ct': window[1]: window width -2 must be > 0"},
      {edit("ct", {{"window", {"40", 80}}}), "edit of 'ct': window[0]: expected a number"},
      {edit("ct", {{"window", {40, 80, 1}}}), "edit of 'ct': window"},
      {edit("ct", {{"window", "bones"}}), "\"bones\" is not a window preset"},
      {edit("axial", {{"transfer_function", {{0, 0, 0, 0, 0}}}}), "applies to volumes only"},
      {edit("ct", {{"opacity", 0.5}, {"transfer_function", {{5, 0, 0, 0, 0}, {1, 1, 1, 1, 1}}}}),
       "edit of 'ct': transfer_function[1][0]: value 1 is below the previous point's 5"},
      {edit("ct", {{"transfer_function", {{0, 0, 0, 0, 2}}}}), "transfer_function[0][4]: 2 is not"},
      {edit("ct", {{"transfer_function", Json::array()}}), "needs at least one point"},
      {edit("ct", {{"transfer_function", std::vector<std::vector<int>>(2000, {0, 0, 0, 0, 0})}}),
       "2000 points; an edit takes at most 1024"},
      {edit("ct", {{"clip_planes", Json::array({{{"point", {0, 0, 0}}, {"normal", {0, 0, 0}}}})}}),
       "clip_planes[0].normal: [0,0,0] is not a usable direction"},
      {edit("ct", {{"clip_planes", Json::array({{{"point", {0, 0, 0}}}})}}),
       "missing required key 'normal'"},
      {edit("axial", {{"opacity", 0.2}, {"window", {40, 0}}}),
       "window[1]: window width 0 must be > 0"},
      {edit("axial", {{"center", {0, 0, 2e6}}}), "edit of 'axial': center[2]: 2000000.0 is not in"},
      {edit("axial", {{"normal", {0, 0, 1}}}), "edit: normal: unknown key"},
  };
  for (const auto& c : cases) {
    const std::string message = error_of([&] { apply_edit(s, c.message); });
    EXPECT_CONTAINS(message, c.says);
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_EQ(s.document.json(), document);
  EXPECT_EQ(s.visible, std::vector<bool>(4, true));
  EXPECT_EQ(s.opacity, (std::vector<float>{1.0f, 1.0f, 0.5f, 1.0f}));
  EXPECT_TRUE(same_bytes(image, draw(s.scene())));
}

TEST(ViewerState, DescribesCameraAndObjects) {
  ViewerState s = small("mpr", {"ct"}, 24);
  apply_edit(s, edit("coronal", {{"visible", false}}));
  const Json d = describe_state(s);
  EXPECT_EQ(d["camera"]["fov_deg"], 32.0);
  EXPECT_EQ(d["initial_camera"]["eye"], Json::array({-380.0, -440.0, 300.0}));
  ASSERT_EQ(d["objects"].size(), 4u);
  const Json& ct = d["objects"][0];
  EXPECT_EQ(ct["name"], "ct");
  EXPECT_EQ(ct["kind"], "volume");
  EXPECT_EQ(ct["transfer_function"].size(), 4u);
  EXPECT_EQ(ct["transfer_function"][2], Json::array({700.0, 1.0, 0.95, 0.85, 0.3}));
  EXPECT_EQ(ct["clip_planes"][0]["normal"], Json::array({0.0, 0.0, -1.0}));
  const Json& coronal = d["objects"][2];
  EXPECT_EQ(coronal["kind"], "plane");
  EXPECT_EQ(coronal["visible"], false);
  EXPECT_EQ(coronal["opacity"], 0.5);
  EXPECT_EQ(coronal["volume"], "ct");
  EXPECT_EQ(coronal["window"], Json::array({40.0, 400.0}));
  EXPECT_EQ(coronal["normal"], Json::array({0.0, 1.0, 0.0}));
  EXPECT_TRUE(coronal.contains("up") && coronal.contains("size") && coronal.contains("center"));
}

// A volume's "window" is its 2-D views' window: an edit writes it to the document (saved, and
// read back), the state reports it, the reading views draw with it, and the 3-D image stays.
TEST(ViewerState, VolumeWindowEditIsTheReadingViewsWindow) {
  ViewerState s = small("mpr", {"ct"}, 24);
  const Json slice = {{"type", "slice"}, {"view", "axial"}, {"point", {0, 0, 0}},
                      {"width", 32},     {"height", 32},    {"mm_per_pixel", 8.0}};
  const std::string before = answer_slice(s, slice).png;
  const Json initial = describe_state(s)["objects"][0]["window"];
  const glm::dvec2 rule = s.initial_windows.at(0).window;
  EXPECT_EQ(initial, Json::array({rule.x, rule.y}));
  const Image image = draw(s.scene());
  EXPECT_FALSE(apply_edit(s, edit("ct", {{"window", {400, 1800}}})));  // the 3-D image stays
  EXPECT_EQ(s.document.json()["objects"][0]["window"], Json::array({400.0, 1800.0}));
  EXPECT_EQ(s.scene().volumes[0].window, glm::dvec2(400, 1800));
  EXPECT_EQ(describe_state(s)["objects"][0]["window"], Json::array({400.0, 1800.0}));
  EXPECT_TRUE(same_bytes(image, draw(s.scene())));
  Json with_window = slice;
  with_window["window"] = {400, 1800};
  const std::string after = answer_slice(s, slice).png;
  EXPECT_NE(after, before);
  EXPECT_EQ(after, answer_slice(s, with_window).png);
  TempDir dir;
  const Scene reloaded = load_scene(dir.write("saved.json", s.document.text()));
  EXPECT_EQ(reloaded.volumes[0].window, glm::dvec2(400, 1800));
  // A preset's name is a window too, written as numbers.
  apply_edit(s, edit("ct", {{"window", "ct-brain"}}));
  const glm::dvec2 brain = *find_window_preset("ct-brain");
  EXPECT_EQ(s.document.json()["objects"][0]["window"], Json::array({brain.x, brain.y}));
}

TEST(ViewerState, HistogramsCountEveryVoxelOfASmallVolume) {
  ViewerState s = small("fusion", {"ct", "pet"}, 24);
  const Json h = describe_histograms(s.scene(), 64);
  ASSERT_TRUE(h.contains("ct") && h.contains("pet"));
  const auto [lo, hi] = s.scene().volumes[0].data->range();
  EXPECT_EQ(h["ct"]["range"], Json::array({lo, hi}));
  ASSERT_EQ(h["ct"]["counts"].size(), 64u);
  int64_t total = 0;
  for (const Json& c : h["ct"]["counts"]) total += c.get<int64_t>();
  EXPECT_EQ(total, static_cast<int64_t>(s.scene().volumes[0].data->voxel_count()));
  EXPECT_GT(h["ct"]["counts"][0].get<int64_t>(), 0);   // the lowest value falls in the first bin
  EXPECT_GT(h["ct"]["counts"][63].get<int64_t>(), 0);  // and the highest in the last
  EXPECT_CONTAINS(error_of([&] { describe_histograms(s.scene(), 0); }), "0 bins");
}

TEST(ViewerState, HistogramsSubsampleALargeVolume) {
  Scene s;
  VolumeData data;
  data.dims = {256, 256, 128};  // 8M voxels: every other voxel along each axis is read
  std::vector<uint16_t> voxels(data.voxel_count());
  for (size_t i = 0; i < voxels.size(); ++i) voxels[i] = static_cast<uint16_t>(i % 4);
  data.voxels = std::move(voxels);
  VolumeObject v;
  v.name = "big";
  v.data = std::make_shared<const VolumeData>(std::move(data));
  s.volumes.push_back(v);
  const Json h = describe_histograms(s, 4);
  // x steps by 2 from 0: only the values 0 and 2 are read, 128 * 128 * 64 voxels.
  EXPECT_EQ(h["big"]["range"], Json::array({0.0, 2.0}));
  EXPECT_EQ(h["big"]["counts"], Json::array({128 * 128 * 32, 0, 0, 128 * 128 * 32}));
}

// The page's preset menu sends a preset's points as an edit: every preset is one the edit takes,
// and it renders as the scene's {"preset": name} does (same points, so same bytes).
TEST(ViewerState, EveryPresetIsAnEditThatRendersAsThePreset) {
  const Json presets = describe_tf_presets();
  EXPECT_EQ(presets.size(), 31u);
  ViewerState s = small("ct-head", {"ct"}, 24);
  for (const auto& [name, points] : presets.items()) {
    SCOPED_TRACE(name);
    ASSERT_GE(points.size(), 2u);
    apply_edit(s, edit("ct", {{"transfer_function", points}}));
  }
  ViewerState by_name = small("ct-head", {"ct"}, 24);
  apply_edit(s, edit("ct", {{"transfer_function", presets["ct-bone"]}}));
  Json preset_document = by_name.document.json();
  preset_document["objects"][0]["transfer_function"] = {{"preset", "ct-bone"}};
  const Scene expected = parse_scene(preset_document.dump(), IMX_EXAMPLES_DIR, "preset");
  Scene edited = s.scene();
  edited.volumes[0].shading = expected.volumes[0].shading;  // an edit keeps the volume's shading
  EXPECT_TRUE(same_bytes(draw(edited), draw(expected)));
}

}  // namespace
}  // namespace imx::server

namespace imx::server {
namespace {

// A 4-D NIfTI of three 16^3 frames (a ball whose radius grows with the frame) and a scene that
// shows it as a MIP beside a (hidden) phantom.
std::filesystem::path write_frames_scene(const TempDir& dir) {
  std::vector<VolumeData> frames;
  for (int f = 0; f < 3; ++f) {
    VolumeData v;
    v.dims = glm::ivec3(16);
    v.index_to_world = glm::dmat4(2.0);
    v.index_to_world[3] = glm::dvec4(-15, -15, -15, 1);
    std::vector<float> voxels;
    for (int k = 0; k < 16; ++k)
      for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i)
          voxels.push_back(glm::length(glm::dvec3(i, j, k) - 7.5) < 3.0 + 2.0 * f ? 100.0f : 0.0f);
    v.voxels = VoxelBuffer<float>(std::move(voxels));
    frames.push_back(std::move(v));
  }
  write_nifti_frames(frames, dir.path() / "ball.nii", 1.0, false);
  const Json head = {{"name", "head"},
                     {"type", "volume"},
                     {"source", {{"phantom", "ct-head"}, {"size", 24}}},
                     {"visible", false},
                     {"transfer_function", {{"preset", "ct-bone"}}}};
  return dir.write("scene.json",
                   test::scene_document({test::mip_volume("ball", dir / "ball.nii", 100), head},
                                        kSize, {0, -120, 0}, {0, 0, 0})
                       .dump());
}

TEST(ViewerState, FrameEditLoadsOnlyThatVolumesFrameAndRoundTrips) {
  TempDir dir;
  ViewerState state = load_viewer_state(write_frames_scene(dir));
  const Json described = describe_state(state);
  EXPECT_EQ(described["objects"][0]["frames"], 3);
  EXPECT_EQ(described["objects"][0]["frame"], 0);
  EXPECT_FALSE(described["objects"][1].contains("frames"));
  const auto head = state.scene().volumes[1].data;
  // As expect_edit_round_trips, with the saved file beside the volume file.
  const Image before_edit = draw(state.scene());
  EXPECT_TRUE(apply_edit(state, edit("ball", {{"frame", 2}})));
  const Image after_edit = draw(state.scene());
  EXPECT_FALSE(same_bytes(before_edit, after_edit)) << "the frame edit changed nothing";
  EXPECT_TRUE(
      same_bytes(after_edit, draw(load_scene(dir.write("saved.json", state.document.text())))));
  EXPECT_EQ(state.scene().volumes[0].frame, 2);
  EXPECT_EQ(state.scene().volumes[0].data->value_at(7, 7, 2), 100.0);  // radius 7 reaches k = 2
  EXPECT_EQ(state.scene().volumes[1].data, head);  // the other volume keeps its data
  EXPECT_EQ(state.document.json()["objects"][0]["source"]["frame"], 2);

  const auto before = state.scene().volumes[0].data;
  const std::string e = error_of([&] { apply_edit(state, edit("ball", {{"frame", 3}})); });
  EXPECT_NE(e.find("frame"), std::string::npos) << e;
  EXPECT_EQ(state.scene().volumes[0].data, before);
  const std::string p = error_of([&] { apply_edit(state, edit("head", {{"frame", 1}})); });
  EXPECT_NE(p.find("frame"), std::string::npos) << p;
}

}  // namespace
}  // namespace imx::server
