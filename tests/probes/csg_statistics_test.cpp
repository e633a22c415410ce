// csg_ray_statistics on scenes with analytic answers: intervals, accepted ranges and per-step
// tests per ray, and the same result for any thread count.
#include <gtest/gtest.h>

#include <string>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/scene.hpp"
#include "probes/csg_statistics.hpp"

namespace imx {
namespace {

// An orthographic view along -y with 1 mm pixels (centres at half millimetres, so no ray grazes
// a face at an integer coordinate), `pixels` square.
Scene ortho_scene(int pixels, const std::string& objects, const std::string& csg) {
  const std::string json = fmt::format(
      R"({{"camera": {{"eye": [0, 200, 0], "target": [0, 0, 0], "up": [0, 0, 1],
                      "projection": "orthographic", "ortho_height": {}}},
          "image": {{"width": {}, "height": {}, "background": [0, 0, 0, 0]}},
          "objects": [{}], "csg": {}}})",
      pixels, pixels, pixels, objects, csg);
  return parse_scene(json, ".", "csg-statistics-test.json");
}

// A 40 mm cube minus a 20 x depth x 20 mm box through it along the view.
Scene box_with_hole(double cutter_depth) {
  const std::string objects = fmt::format(
      R"({{"name": "part", "type": "mesh", "source": {{"primitive": "box", "size": 40}}}},
         {{"name": "cutter", "type": "mesh",
          "source": {{"primitive": "box", "size": [20, {}, 20]}}}})",
      cutter_depth);
  return ortho_scene(64, objects, R"({"op": "difference", "a": "part", "b": "cutter"})");
}

TEST(CsgRayStatistics, BoxWithAHoleHasOneRangeThroughTheSolidAndNoneThroughTheHole) {
  const CsgRayStatistics s = csg_ray_statistics(box_with_hole(60.0), 1);
  EXPECT_EQ(s.width, 64);
  EXPECT_EQ(s.height, 64);
  EXPECT_EQ(s.rays, 64 * 64);
  EXPECT_EQ(s.meeting, 40 * 40);  // the cutter's 20 x 20 footprint lies inside the part's
  // 1200 solid rays with one range each and no more anywhere: the 400 hole rays have none.
  EXPECT_EQ(s.ranges, 1200);
  EXPECT_EQ(s.max_ranges, 1);
  // Intervals between boundary groups (the eye's side of the first one is none): solid rays
  // cross the part once, 1; hole rays [cutter], [cutter and part], [cutter]: 3.
  EXPECT_EQ(s.intervals, 1200 * 1 + 400 * 3);
  EXPECT_EQ(s.max_intervals, 3);
  EXPECT_DOUBLE_EQ(s.mean_intervals(), 2400.0 / 1600.0);
  EXPECT_DOUBLE_EQ(s.mean_ranges(), 1200.0 / 1600.0);
  // Meshes are present wherever they enclose a point: no step needs a test.
  EXPECT_EQ(s.tested, 0);
  EXPECT_EQ(s.inconsistent, 0);
  EXPECT_TRUE(s.inconsistent_examples.empty());
}

TEST(CsgRayStatistics, CoplanarCutterFacesAreOneGroup) {
  // The cutter exactly as deep as the part: its faces and the part's coincide, so a hole ray
  // meets two groups and one interval between them like a solid one, and accepts nothing.
  const CsgRayStatistics s = csg_ray_statistics(box_with_hole(40.0), 1);
  EXPECT_EQ(s.meeting, 1600);
  EXPECT_EQ(s.ranges, 1200);
  EXPECT_EQ(s.intervals, 1600);
  EXPECT_EQ(s.max_intervals, 1);
  EXPECT_EQ(s.inconsistent, 0);
}

TEST(CsgRayStatistics, ThreadCountDoesNotChangeTheResult) {
  const Scene scene = box_with_hole(60.0);
  EXPECT_EQ(csg_ray_statistics(scene, 1), csg_ray_statistics(scene, 2));
}

TEST(CsgRayStatistics, OpacityPresentVolumeNeedsTheStepTest) {
  // The sphere phantom (value = 44.8 mm - |p|) as an opaque ball minus the half-space x > 0: rays
  // left of x = 0 accept the ball's part, where only its TF says whether a step shows; rays
  // right of it are inside the cutter, which rejects every interval.
  const std::string objects = R"(
    {"name": "ball", "type": "volume", "source": {"phantom": "sphere", "size": 64},
     "transfer_function": {"points": [[0, 1, 1, 1, 0], [0.5, 1, 1, 1, 1]]}},
    {"name": "half", "type": "mesh", "source": {"primitive": "box", "size": [100, 300, 300]},
     "transform": {"translate": [50, 0, 0]}})";
  const Scene scene =
      ortho_scene(128, objects, R"({"op": "difference", "a": "ball", "b": "half"})");
  const CsgRayStatistics s = csg_ray_statistics(scene, 2);
  EXPECT_EQ(s.rays, 128 * 128);
  EXPECT_GT(s.meeting, 0);
  EXPECT_GT(s.tested, 0);
  EXPECT_LT(s.tested, s.meeting);
  EXPECT_EQ(s.tested, s.ranges);  // one range per accepted ray, and each needs the test
  EXPECT_EQ(s.max_ranges, 1);
  EXPECT_EQ(s.inconsistent, 0);
  EXPECT_EQ(s, csg_ray_statistics(scene, 1));
}

TEST(CsgRayStatistics, SceneWithoutCsgIsAnError) {
  const Scene scene = ortho_scene(
      16, R"({"name": "part", "type": "mesh", "source": {"primitive": "box", "size": 4}})", "null");
  EXPECT_THROW(csg_ray_statistics(scene, 1), Error);
}

}  // namespace
}  // namespace imx
