// The zfight command: the z-fighting metric of methods on a scene, as JSON.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "scene_fixture.hpp"

namespace imx::test {
namespace {

TEST(CliZFight, MeasuresEachMethodAndPrintsJson) {
  CliResult r = run_lab("zfight " + example_scene("coplanar-tilted") +
                        " --width 48 --height 48 --set camera.fov_deg=12 --method dfb "
                        "--method dfb-sfm --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j["methods"].size(), 2u);
  EXPECT_GT(j["methods"][0]["pixels"].get<long>(), 50);
  EXPECT_GT(j["methods"][0]["speckle"].get<double>(), j["methods"][1]["speckle"].get<double>());
  EXPECT_LT(j["methods"][1]["std_dev"].get<double>(), 1.0 / 255.0);
}

TEST(CliZFight, SceneWithoutCoplanarSurfacesIsAClearError) {
  CliResult r =
      run_lab("zfight " + example_scene("shells") + " --width 32 --height 32 --method dfb");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("no coplanar surfaces"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace imx::test
