// The csg command: primitives, clipping states and intervals per ray of CSG scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "scene_fixture.hpp"

namespace imx::test {
namespace {

TEST(CliCsg, CutawayHasThreePrimitivesAndTwoStates) {
  CliResult r = run_lab("csg " + example_scene("csg-cutaway") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j["primitives"].size(), 3u);
  // Digits by first appearance in union(difference(skin, ball), bone).
  EXPECT_EQ(j["legend"], "skin=0 ball=1 bone=2");
  EXPECT_EQ(j["primitives"][1]["name"], "ball");
  EXPECT_EQ(j["primitives"][1]["kind"], "mesh");
  EXPECT_EQ(j["primitives"][1]["presence"], "region");
  EXPECT_EQ(j["primitives"][2]["presence"], "opacity");
  // skin − ball is 102 and bone is 221. Merging needs two states differing in one 1/0 digit, and
  // neither covers the other; the ball's box lies inside the skin's, so pruning keeps ball's 0.
  const std::vector<std::string> states{"102", "221"};
  EXPECT_EQ(j["products"], states);
  EXPECT_EQ(j["stages"]["merge"], states);
  EXPECT_EQ(j["stages"]["pruning"], states);
  EXPECT_FALSE(j["stages"].contains("full"));  // csg_simplify merge, the default
  EXPECT_EQ(j["states"], states);
  EXPECT_TRUE(j["pruned"].empty());
  EXPECT_FALSE(j.contains("intervals"));
}

TEST(CliCsg, FullSimplificationShowsItsStage) {
  CliResult r =
      run_lab("csg " + example_scene("csg-cutaway") + " --json --set render.csg_simplify=full");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto j = nlohmann::json::parse(r.output);
  ASSERT_TRUE(j["stages"].contains("full"));
  EXPECT_EQ(j["stages"]["full"], j["states"]);
}

TEST(CliCsg, SlicedAppleHasTwentyStates) {
  CliResult r = run_lab("csg " + example_scene("csg-sliced") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["primitives"].size(), 21u);
  EXPECT_EQ(j["states"].size(), 20u);  // apple ∩ (slice1 ∪ … ∪ slice20): one per slice
}

TEST(CliCsg, HumanOutputHasLegendAndStates) {
  CliResult r = run_lab("csg " + example_scene("csg-cutaway"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("legend: skin=0 ball=1 bone=2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("states (2): 102 221"), std::string::npos) << r.output;
}

TEST(CliCsg, SceneWithoutCsgIsAOneLineError) {
  const std::string scene = example_scene("shells");
  CliResult r = run_lab("csg " + scene);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_NE(r.output.find(scene + ": has no csg block"), std::string::npos) << r.output;
}

TEST(CliCsg, IntervalsCountEveryRay) {
  CliResult r =
      run_lab("csg " + example_scene("csg-cutaway") + " --intervals --json --width 32 --height 32");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto j = nlohmann::json::parse(r.output);
  const auto& iv = j["intervals"];
  EXPECT_EQ(iv["rays"].get<long>(), 1024);
  EXPECT_GT(iv["meeting"].get<long>(), 0);
  EXPECT_GT(iv["intervals_per_ray"]["mean"].get<double>(), 0.0);  // the seed's PSI
  EXPECT_GE(iv["intervals_per_ray"]["max"].get<int>(), 1);
  EXPECT_GT(iv["ranges_per_ray"]["mean"].get<double>(), 0.0);
}

}  // namespace
}  // namespace imx::test
