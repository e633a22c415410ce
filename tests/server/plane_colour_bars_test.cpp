// The viewer's state carries the planes' colour bars as render --colorbar builds them: one per
// colour map the planes show (planes of one map joined), none for grey anatomy planes.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "presets/colormap.hpp"
#include "server/viewer_state.hpp"
#include "temp_dir.hpp"

namespace imx::server {
namespace {

using Json = nlohmann::json;

TEST(PlaneColourBars, OneBarPerColourMapThePlanesShow) {
  test::TempDir dir;
  auto plane = [](const char* name, const char* colormap, Json normal) {
    return Json{{"name", name},        {"type", "plane"},  {"volume", "pet"},
                {"center", {0, 0, 0}}, {"normal", normal}, {"window", {3, 4}},
                {"colormap", colormap}};
  };
  const Json scene = {{"camera", {{"eye", {0, -300, 0}}, {"target", {0, 0, 0}}, {"up", {0, 0, 1}}}},
                      {"image", {{"width", 16}, {"height", 16}}},
                      {"objects",
                       {{{"name", "pet"},
                         {"type", "volume"},
                         {"source", {{"phantom", "pet"}, {"size", 16}}},
                         {"visible", false}},
                        plane("axial", "hot", {0, 0, 1}),
                        plane("coronal", "hot", {0, 1, 0}),
                        plane("sagittal", "grey", {1, 0, 0})}}};
  const std::filesystem::path file = dir.path() / "planes.json";
  std::ofstream(file) << scene.dump();
  const Json bars = describe_state(load_viewer_state(file))["colour_bars"];
  ASSERT_EQ(bars.size(), 1u) << bars.dump();
  EXPECT_EQ(bars[0]["shown_by"], "axial, coronal");
  ASSERT_EQ(bars[0]["colors"].size(), 64u);
  // The top of the window is the map's last colour.
  const glm::vec3 top = colormap_rgb(Colormap::hot, 1.0f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(bars[0]["colors"][63][c].get<double>(), top[c], 1e-6);
}

}  // namespace
}  // namespace imx::server
