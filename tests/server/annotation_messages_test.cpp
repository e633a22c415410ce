// The viewer's measurement messages (src/server/annotation_messages.hpp): `annotations` edits
// the document (in its own space) and every bad list gets one error naming the field with nothing
// changed; `measure` answers the ROI statistics; `pick` finds the first shown surface on a ray.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "expect_error.hpp"
#include "server/annotation_messages.hpp"
#include "server/viewer_state.hpp"
#include "temp_dir.hpp"

namespace imx::server {
namespace {

using Json = nlohmann::json;

// A 16³ cube phantom and a sphere of radius 20 about the origin, in `space`.
ViewerState session(const test::TempDir& dir, const std::string& space = "LPS") {
  const Json scene = {
      {"space", space},
      {"camera", {{"eye", {0, -400, 0}}, {"target", {0, 0, 0}}, {"up", {0, 0, 1}}}},
      {"image", {{"width", 64}, {"height", 64}}},
      {"objects",
       {{{"name", "cube"}, {"type", "volume"}, {"source", {{"phantom", "cube"}, {"size", 16}}}},
        {{"name", "ball"},
         {"type", "mesh"},
         {"source", {{"primitive", "sphere"}, {"radius", 20}, {"segments", 64}}}}}}};
  const std::filesystem::path file = dir.path() / "scene.json";
  std::ofstream(file) << scene.dump();
  return load_viewer_state(file);
}

Json ruler(double x0, double x1) {
  return {{"kind", "ruler"}, {"points", {{x0, 1, 2}, {x1, 1, 2}}}};
}

TEST(AnnotationMessages, EditTheDocumentInItsSpace) {
  test::TempDir dir;
  ViewerState state = session(dir, "RAS");
  EXPECT_TRUE(apply_annotations(state, {{"type", "annotations"}, {"annotations", {ruler(3, 7)}}}));
  ASSERT_EQ(state.document.annotations().size(), 1u);
  EXPECT_EQ(state.document.annotations()[0].points[0], glm::dvec3(3, 1, 2));  // LPS, as sent
  EXPECT_EQ(state.document.json()["annotations"][0]["points"][0], Json({-3.0, -1.0, 2.0}));
  EXPECT_EQ(describe_state(state)["annotations"][0]["points"][1], Json({7.0, 1.0, 2.0}));
  // The same list changes nothing; an empty one removes the key.
  EXPECT_FALSE(apply_annotations(state, {{"type", "annotations"}, {"annotations", {ruler(3, 7)}}}));
  EXPECT_TRUE(apply_annotations(state, {{"type", "annotations"}, {"annotations", Json::array()}}));
  EXPECT_FALSE(state.document.json().contains("annotations"));
}

TEST(AnnotationMessages, HostileListsGetOneErrorAndChangeNothing) {
  test::TempDir dir;
  ViewerState state = session(dir);
  apply_annotations(state, {{"type", "annotations"}, {"annotations", {ruler(0, 5)}}});
  const Json before = state.document.json();
  Json many = Json::array();
  for (int i = 0; i < 300; ++i) many.push_back({std::cos(i * 0.02), std::sin(i * 0.02), 0.0});
  const std::pair<Json, std::string> cases[] = {
      {{{"kind", "circle"}, {"points", {{0, 0, 0}}}}, "annotations[1].kind: "},
      {{{"kind", "polygon"}, {"points", many}},
       "annotations[1].points: a polygon has 3 to 256 points, not 300"},
      {{{"kind", "ruler"}, {"points", {{0, 0, 0}, {1, "x", 0}}}}, "annotations[1].points[1]"},
      {{{"kind", "ruler"}, {"points", {{0, 0, 0}, {1, 1e308, 0}}}}, "annotations[1].points[1]"},
      {{{"kind", "angle"}, {"points", {{0, 0, 0}, {0, 0, 0}, {1, 0, 0}}}}, "an angle's arms"},
      {{{"kind", "ellipse"}, {"points", {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}}},
       "an ellipse's semi-axes"},
      {{{"kind", "ellipse"}, {"points", {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}}}, {"volume", "ball"}},
       "'ball' is a mesh, not a volume"},
  };
  for (const auto& c : cases) {
    const Json& bad = c.first;  // not a structured binding: a lambda may not capture one in C++20
    const auto& message = c.second;
    const std::string error = test::error_of([&] {
      apply_annotations(state, {{"type", "annotations"}, {"annotations", {ruler(0, 5), bad}}});
    });
    EXPECT_CONTAINS(error, message);
    EXPECT_CONTAINS(error, "annotations: annotations[1]");  // the message, then the field
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_EQ(state.document.json(), before) << error;
    EXPECT_EQ(state.document.annotations().size(), 1u);
  }
  EXPECT_CONTAINS(test::error_of([&] {
                    apply_annotations(state, {{"type", "annotations"}, {"annotations", "x"}});
                  }),
                  "annotations: annotations: expected an array");
  EXPECT_CONTAINS(test::error_of([&] {
                    apply_annotations(state, {{"type", "annotations"}, {"list", Json::array()}});
                  }),
                  "unknown key");
}

TEST(AnnotationMessages, MeasureAnswersTheStatistics) {
  test::TempDir dir;
  const ViewerState state = session(dir);
  const VolumeObject& cube = state.scene().volumes[0];
  // A square over one layer's centres, from the grid's own placement: its voxels by index.
  const glm::dmat4& m = cube.index_to_world;
  const auto at = [&](double i, double j) { return glm::dvec3(m * glm::dvec4(i, j, 8, 1)); };
  Json square = {{"kind", "polygon"}, {"volume", "cube"}, {"points", Json::array()}};
  for (const glm::dvec3& p : {at(1.5, 1.5), at(13.5, 1.5), at(13.5, 13.5), at(1.5, 13.5)})
    square["points"].push_back({p.x, p.y, p.z});
  const Json answer = answer_measure(
      state, {{"type", "measure"}, {"seq", 7}, {"annotations", {ruler(0, 5), square}}});
  EXPECT_EQ(answer["seq"], 7);
  EXPECT_DOUBLE_EQ(answer["measurements"][0]["length_mm"].get<double>(), 5.0);
  const Json& s = answer["measurements"][1];
  EXPECT_EQ(s["voxels"], 144);  // centres 2..13 along i and j
  double sum = 0, sq = 0, lo = 1e300, hi = -1e300;
  for (int j = 2; j <= 13; ++j)
    for (int i = 2; i <= 13; ++i) {
      const double v = cube.data->value_at(i, j, 8);
      sum += v;
      sq += v * v;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  const double mean = sum / 144;
  EXPECT_NEAR(s["mean"].get<double>(), mean, 1e-9);
  EXPECT_NEAR(s["sd"].get<double>(), std::sqrt(std::max(0.0, sq / 144 - mean * mean)), 1e-6);
  EXPECT_EQ(s["min"].get<double>(), lo);
  EXPECT_EQ(s["max"].get<double>(), hi);
  EXPECT_EQ(s["volume"], "cube");
  Json too_many = Json::array();
  for (int i = 0; i < 65; ++i) too_many.push_back(ruler(0, 1));
  EXPECT_CONTAINS(test::error_of([&] {
                    answer_measure(state, {{"type", "measure"}, {"annotations", too_many}});
                  }),
                  "65 annotations, more than the 64");
}

TEST(AnnotationMessages, PickFindsTheNearestShownSurface) {
  test::TempDir dir;
  ViewerState state = session(dir);
  const Json centre = {{"type", "pick"}, {"x", 32}, {"y", 32}, {"width", 64}, {"height", 64}};
  // The cube hidden: the view's centre meets the sphere's front, y = -20.
  state.visible[0] = false;
  const Json ball = answer_pick(state, centre);
  ASSERT_TRUE(ball["point"].is_array()) << ball.dump();
  EXPECT_EQ(ball["object"], "ball");
  EXPECT_NEAR(ball["point"][1].get<double>(), -20.0, 0.1);
  EXPECT_NEAR(ball["point"][0].get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(ball["point"][2].get<double>(), 0.0, 1e-6);
  // Both shown: the cube's half opacity lies in front of the sphere, so it is the nearest.
  state.visible[0] = true;
  const Json both = answer_pick(state, centre);
  EXPECT_EQ(both["object"], "cube");
  EXPECT_LT(both["point"][1].get<double>(), -20.0);
  const Json miss =
      answer_pick(state, {{"type", "pick"}, {"x", 1}, {"y", 1}, {"width", 64}, {"height", 64}});
  EXPECT_TRUE(miss["point"].is_null());
  EXPECT_CONTAINS(
      test::error_of([&] {
        answer_pick(state, {{"type", "pick"}, {"x", 100}, {"y", 1}, {"width", 64}, {"height", 64}});
      }),
      "pick: x:");
}

}  // namespace
}  // namespace imx::server
