// Scene files' transfer functions from presets and preset files, and planes' window presets and
// colour maps.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "intermix/scene.hpp"
#include "presets/colormap.hpp"
#include "presets/colormap_tf.hpp"
#include "presets/slicer_volume_property.hpp"
#include "presets/tf_adjust.hpp"
#include "presets/volume_presets.hpp"
#include "scene/reading_planes.hpp"
#include "scene/scene_parsers.hpp"
#include "scene_fixture.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::parse;
using test::parse_error;

// A scene with one small phantom volume whose "transfer_function" (and more keys) is `tf`.
std::string volume_scene(const std::string& tf, const std::string& more = "") {
  return fmt::format(
      R"({{"camera": {{"eye": [0, -100, 0]}},
          "objects": [{{"name": "ct", "type": "volume", "source": {{"phantom": "cube", "size": 8}},
          "transfer_function": {}{}}}]}})",
      tf, more);
}

void expect_same_points(const TransferFunction& a, const TransferFunction& b) {
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].value, b.points[i].value) << i;
    EXPECT_EQ(a.points[i].rgba, b.points[i].rgba) << i;
  }
}

TEST(TransferFunctionScene, PresetGivesSlicersMergedPointsAndShading) {
  Scene s = parse(volume_scene(R"({"preset": "ct-bone"})"));
  const VolumeObject& v = s.volumes[0];
  SlicerVolumeProperty p = *find_volume_preset("ct-bone");
  expect_same_points(v.transfer_function, to_transfer_function(p));
  EXPECT_EQ(v.transfer_function.unit_distance, 1.0);
  EXPECT_TRUE(v.shading.enabled);  // the preset's shading, as the volume gives none
  EXPECT_FLOAT_EQ(v.shading.ambient, 0.1f);
  EXPECT_FLOAT_EQ(v.shading.shininess, 10.0f);
  // Slicer's spelling finds it too; the scene's own shading wins over the preset's.
  Scene own = parse(volume_scene(R"({"preset": "CT-Bone", "unit_distance": 2})",
                                 R"(, "shading": {"enabled": false})"));
  expect_same_points(own.volumes[0].transfer_function, to_transfer_function(p));
  EXPECT_EQ(own.volumes[0].transfer_function.unit_distance, 2.0);
  EXPECT_FALSE(own.volumes[0].shading.enabled);
  EXPECT_TRUE(own.notes.empty());
}

TEST(TransferFunctionScene, ShiftAndScaleMovePresetPointsAboutTheEffectiveRangeCentre) {
  Scene s = parse(volume_scene(R"({"preset": "ct-bone", "shift": 100, "scale": 0.5})"));
  const auto& got = s.volumes[0].transfer_function.points;
  const double centre = 0.5 * (-16.4458 + 641.385);
  const double original[] = {-3024, -16.4458, 641.385, 3071};
  ASSERT_EQ(got.size(), 4u);
  for (int i = 0; i < 4; ++i)
    EXPECT_DOUBLE_EQ(got[i].value, centre + 0.5 * (original[i] - centre) + 100.0) << i;
  // On plain points the centre is the middle of their span.
  Scene pts = parse(volume_scene(
      R"({"points": [[0, 0, 0, 0, 0], [100, 1, 1, 1, 1]], "shift": -10, "scale": 3})"));
  EXPECT_DOUBLE_EQ(pts.volumes[0].transfer_function.points[0].value, 50.0 - 150.0 - 10.0);
  EXPECT_DOUBLE_EQ(pts.volumes[0].transfer_function.points[1].value, 50.0 + 150.0 - 10.0);
}

TEST(TransferFunctionScene, BadPresetKeysGetOneClearError) {
  std::string e = parse_error(volume_scene(R"({"preset": "ct-bnoe"})"));
  EXPECT_CONTAINS(e,
                  "objects[0].transfer_function.preset: \"ct-bnoe\" is not a volume-rendering "
                  "preset (did you mean 'ct-bone'?); they are: ct-aaa, ct-aaa2");
  EXPECT_CONTAINS(e, "mr-t2-brain");
  e = parse_error(volume_scene(R"({"preset": "ct-bone", "points": [[0, 1, 1, 1, 1]]})"));
  EXPECT_CONTAINS(e, "give one of \"points\", \"preset\", \"file\" and \"colormap\", not several");
  e = parse_error(volume_scene(R"({"unit_distance": 1})"));
  EXPECT_CONTAINS(e,
                  "missing required key 'points' (or a \"preset\" name, a preset \"file\" or a "
                  "\"colormap\" with a \"range\")");
  e = parse_error(volume_scene(R"({"preset": "ct-bone", "scale": 0})"));
  EXPECT_CONTAINS(e, "objects[0].transfer_function.scale");
  e = parse_error(volume_scene(R"({"preset": "ct-bone", "name": "x"})"));
  EXPECT_CONTAINS(e, "objects[0].transfer_function.name: only a ParaView colour-map \"file\"");
  e = parse_error(volume_scene(R"({"preset": "ct-bone", "shfit": 3})"));
  EXPECT_CONTAINS(e, "shift");
  // Scaled beyond what the renderer's float table spans (each end alone is still a float).
  e = parse_error(
      volume_scene(R"({"points": [[-1e38, 0, 0, 0, 0], [1e38, 1, 1, 1, 1]], "scale": 2})"));
  EXPECT_CONTAINS(e, "wider than a float can hold");
}

TEST(TransferFunctionScene, PresetWithGradientOpacityLeavesANote) {
  Scene s = parse(volume_scene(R"({"preset": "uct-skull"})"));
  ASSERT_EQ(s.notes.size(), 1u);
  EXPECT_CONTAINS(s.notes[0],
                  "preset 'uct-skull' has a gradient opacity, which intermix does "
                  "not apply");
}

TEST(TransferFunctionScene, VpAndParaviewFilesResolveAgainstTheSceneFolder) {
  test::TempDir dir;
  dir.write("tf/bone.vp",
            "1\n0\n0.3\n0.6\n0.5\n40\n4 0 0 100 1\n4 0 1 255 1\n8 0 1 0 0 100 0 0 1\n");
  nlohmann::json maps = nlohmann::json::array(
      {{{"Name", "A"}, {"RGBPoints", {0, 0, 0, 0, 10, 1, 1, 1}}},
       {{"Name", "B"}, {"RGBPoints", {0, 1, 0, 0, 10, 0, 1, 0}}, {"Points", {0, 0.5, 0.5, 0}}}});
  dir.write("tf/maps.json", maps.dump());

  Scene vp = parse(volume_scene(R"({"file": "tf/bone.vp", "shift": 10})"), {}, dir.path());
  const auto& p = vp.volumes[0].transfer_function.points;
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].value, 10.0);
  EXPECT_EQ(p[1].rgba, glm::vec4(0, 0, 1, 1));
  EXPECT_FALSE(vp.volumes[0].shading.enabled);  // the file's "shade" is 0
  EXPECT_FLOAT_EQ(vp.volumes[0].shading.specular, 0.5f);

  Scene pv = parse(volume_scene(R"({"file": "tf/maps.json", "name": "B"})"), {}, dir.path());
  EXPECT_EQ(pv.volumes[0].transfer_function.points[1].rgba, glm::vec4(0, 1, 0, 0.5f));
  EXPECT_FALSE(pv.volumes[0].shading.enabled);  // ParaView maps carry no shading
  Scene ramp = parse(volume_scene(R"({"file": "tf/maps.json", "name": "A"})"), {}, dir.path());
  ASSERT_EQ(ramp.notes.size(), 1u);
  EXPECT_CONTAINS(ramp.notes[0], "no opacity \"Points\"");

  std::string e = parse_error(volume_scene(R"({"file": "tf/maps.json"})"), {}, dir.path());
  EXPECT_CONTAINS(e, "objects[0].transfer_function.file: ");
  EXPECT_CONTAINS(e, "maps.json: holds 2 colour maps; choose one with \"name\": 'A', 'B'");
  e = parse_error(volume_scene(R"({"file": "tf/bone.vp", "name": "A"})"), {}, dir.path());
  EXPECT_CONTAINS(e, "transfer_function.name: only a ParaView colour-map file (.json)");
  dir.write("tf/bad.vp", "1\n0\n0.3\n0.6\n0.5\n40\n4 0 0 100 1\n4 0 1 255 1\n8 0 1 0 0 100 0 0\n");
  e = parse_error(volume_scene(R"({"file": "tf/bad.vp"})"), {}, dir.path());
  EXPECT_CONTAINS(e, "scene.json: objects[0].transfer_function.file: ");
  EXPECT_CONTAINS(e, "bad.vp: line 9 (colour): count 8 does not match the 7 numbers");
  dir.write("tf/x.txt", "");
  e = parse_error(volume_scene(R"({"file": "tf/x.txt"})"), {}, dir.path());
  EXPECT_CONTAINS(e, "is neither a 3D Slicer volume property (.vp) nor a ParaView colour map");
  e = parse_error(volume_scene(R"({"file": "tf/none.vp"})"), {}, dir.path());
  EXPECT_CONTAINS(e, "no such file");
}

// ---- colour-map form ------------------------------------------------------------------------

TEST(TransferFunctionScene, ColormapFormResolvesToTheRulesPoints) {
  Scene s = parse(volume_scene(
      R"({"colormap": "cold-hot", "range": [3, 8], "threshold": 4, "symmetric": true,
          "opacity": 0.5, "unit_distance": 2})"));
  ColormapTransferFunction c;
  c.map = Colormap::cold_hot;
  c.lo = 3.0;
  c.hi = 8.0;
  c.threshold = 4.0;
  c.symmetric = true;
  c.opacity = 0.5f;
  expect_same_points(s.volumes[0].transfer_function, colormap_transfer_function(c));
  EXPECT_EQ(s.volumes[0].transfer_function.unit_distance, 2.0);
  // Every name of presets/colormap.hpp is a scene-file name.
  for (std::string_view name : kColormapNames)
    EXPECT_NO_THROW(
        parse(volume_scene(fmt::format(R"({{"colormap": "{}", "range": [0, 1]}})", name))))
        << name;
}

// A statistical map's units label (its colour bar says "t"), which the file cannot say.
TEST(TransferFunctionScene, VolumeUnitsLabel) {
  EXPECT_EQ(parse(volume_scene(R"({"colormap": "hot", "range": [3, 8]})", R"(, "units": "t")"))
                .volumes[0]
                .units,
            "t");
  EXPECT_EQ(parse(volume_scene(R"({"colormap": "hot", "range": [3, 8]})")).volumes[0].units, "");
  EXPECT_CONTAINS(parse_error(volume_scene(R"({"colormap": "hot", "range": [3, 8]})",
                                           R"(, "units": "a very long units label")")),
                  "objects[0].units: a units label has at most 16 characters");
}

TEST(TransferFunctionScene, ColormapFormRefusesWithOneLineNamingTheField) {
  std::string e = parse_error(volume_scene(R"({"colormap": "hott", "range": [3, 8]})"));
  EXPECT_CONTAINS(e,
                  "objects[0].transfer_function.colormap: \"hott\" is not a colour map (did "
                  "you mean 'hot'?); they are: grey, hot, inferno, viridis, plasma, jet, "
                  "cold-hot, red-yellow, blue-lightblue");
  e = parse_error(volume_scene(R"({"colormap": "hot"})"));
  EXPECT_CONTAINS(e, "objects[0].transfer_function: missing required key 'range'");
  e = parse_error(volume_scene(R"({"colormap": "hot", "range": [8, 3]})"));
  EXPECT_CONTAINS(e, "objects[0].transfer_function.range: [8, 3]: the first value must be below");
  e = parse_error(volume_scene(R"({"colormap": "hot", "range": [-1, 3], "symmetric": true})"));
  EXPECT_CONTAINS(e,
                  "transfer_function.range: [-1, 3]: with \"symmetric\" the range is of "
                  "magnitudes");
  e = parse_error(volume_scene(R"({"colormap": "hot", "range": [3, 8], "threshold": 9})"));
  EXPECT_CONTAINS(e, "transfer_function.threshold: 9 is above the range's end 8");
  e = parse_error(
      volume_scene(R"({"colormap": "hot", "range": [3, 8], "threshold": -2, "symmetric": true})"));
  EXPECT_CONTAINS(e, "transfer_function.threshold");
  e = parse_error(volume_scene(R"({"colormap": "hot", "range": [3, 8], "opacity": 2})"));
  EXPECT_CONTAINS(e, "transfer_function.opacity");
  e = parse_error(volume_scene(R"({"points": [[0, 1, 1, 1, 1]], "threshold": 3})"));
  EXPECT_CONTAINS(e, "transfer_function.threshold: applies only with a \"colormap\"");
  e = parse_error(volume_scene(R"({"preset": "ct-bone", "colormap": "hot", "range": [3, 8]})"));
  EXPECT_CONTAINS(e, "not several");
}

// ---- planes --------------------------------------------------------------------------------

std::string plane_scene(const std::string& plane_keys) {
  return fmt::format(
      R"({{"camera": {{"eye": [0, -100, 0]}},
          "objects": [{{"name": "ct", "type": "volume", "source": {{"phantom": "cube", "size": 8}},
          "transfer_function": {{"points": [[0, 0, 0, 0, 0]]}}}},
        {{"name": "axial", "type": "plane", "volume": "ct", "normal": [0, 0, 1]{}}}]}})",
      plane_keys);
}

TEST(PlanePresets, WindowByNameOrAsCentreAndWidth) {
  EXPECT_EQ(parse(plane_scene(R"(, "window": "ct-brain")")).planes[0].window, glm::dvec2(50, 100));
  EXPECT_EQ(parse(plane_scene(R"(, "window": "CT-Lung")")).planes[0].window,
            glm::dvec2(-500, 1400));
  EXPECT_EQ(parse(plane_scene(R"(, "window": [10, 20])")).planes[0].window, glm::dvec2(10, 20));
  const Scene no_window = parse(plane_scene(""));  // the volume's reading window
  EXPECT_EQ(no_window.planes[0].window, reading_window(no_window.volumes[0]));
  std::string e = parse_error(plane_scene(R"(, "window": "ct-brian")"));
  EXPECT_CONTAINS(e,
                  "objects[1].window: \"ct-brian\" is not a window preset (did you mean "
                  "'ct-brain'?); they are: ct-bone, ct-air, ct-brain, ct-abdomen, ct-lung, "
                  "pet, dti");
  e = parse_error(plane_scene(R"(, "window": [10, 0])"));
  EXPECT_CONTAINS(e, "objects[1].window[1]: window width 0 must be > 0");
  e = parse_error(plane_scene(R"(, "window": 40)"));
  EXPECT_CONTAINS(e, "expected [centre, width] or a window preset name");
}

TEST(PlanePresets, WindowDefaultsToTheVolumesDisplayWindow) {
  Scene scene = parse(plane_scene(""));
  const auto types = std::map<std::string, std::string>{{"ct", "volume"}};
  nlohmann::json plane = {
      {"name", "p"}, {"type", "plane"}, {"volume", "ct"}, {"normal", {0, 0, 1}}};
  scene_json::JsonReader r(plane, "scene.json", "objects[1]");
  scene.volumes[0].display_window = glm::dvec2(-600, 1600);
  EXPECT_EQ(scene_json::parse_plane_object(r, scene, types).window, glm::dvec2(-600, 1600));
  plane["window"] = "ct-bone";  // an explicit window wins
  EXPECT_EQ(scene_json::parse_plane_object(r, scene, types).window, glm::dvec2(400, 1000));
  plane.erase("window");
  scene.volumes[0].display_window.reset();
  // Without one: the volume's reading window (the 2-D views' initial window, its own rule's
  // tests in tests/volume), not CT's soft-tissue [40, 400].
  const glm::dvec2 window = scene_json::parse_plane_object(r, scene, types).window;
  EXPECT_EQ(window, reading_window(scene.volumes[0]));
  EXPECT_NE(window, glm::dvec2(40, 400));
  // A plane without a volume keeps the soft-tissue default.
  nlohmann::json free_plane = {
      {"name", "q"}, {"type", "plane"}, {"center", {0, 0, 0}}, {"normal", {0, 0, 1}}, {"size", 10}};
  scene_json::JsonReader f(free_plane, "scene.json", "objects[2]");
  EXPECT_EQ(scene_json::parse_plane_object(f, scene, types).window, glm::dvec2(40, 400));
}

TEST(PlanePresets, ColormapByName) {
  EXPECT_EQ(parse(plane_scene("")).planes[0].colormap, Colormap::grey);
  EXPECT_EQ(parse(plane_scene(R"(, "colormap": "viridis")")).planes[0].colormap, Colormap::viridis);
  EXPECT_EQ(parse(plane_scene(R"(, "colormap": "hot")")).planes[0].colormap, Colormap::hot);
  EXPECT_EQ(parse(plane_scene(R"(, "colormap": "inferno")")).planes[0].colormap, Colormap::inferno);
  std::string e = parse_error(plane_scene(R"(, "colormap": "gray")"));
  EXPECT_CONTAINS(e, "objects[1].colormap");
  EXPECT_CONTAINS(e, "grey");
}

TEST(PlanePresets, ThresholdAndSymmetric) {
  const PlaneObject p = parse(plane_scene(R"(, "threshold": 3, "symmetric": true)")).planes[0];
  EXPECT_EQ(p.threshold, 3.0);
  EXPECT_TRUE(p.symmetric);
  EXPECT_EQ(parse(plane_scene("")).planes[0].threshold, std::nullopt);
  EXPECT_CONTAINS(parse_error(plane_scene(R"(, "threshold": -3, "symmetric": true)")),
                  "objects[1].threshold");
  EXPECT_CONTAINS(
      parse_error(R"({"camera": {"eye": [0, -100, 0]}, "objects": [{"name": "p", "type": "plane",
          "center": [0, 0, 0], "normal": [0, 0, 1], "size": 10, "threshold": 2}]})"),
      "objects[0].threshold: applies only to a plane showing a \"volume\"");
}

}  // namespace
}  // namespace imx
