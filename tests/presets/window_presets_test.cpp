#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "presets/window_presets.hpp"
#include "shared_data.hpp"

namespace imx {
namespace {

TEST(WindowPresets, NamesGiveCentreAndWidth) {
  EXPECT_EQ(find_window_preset("ct-brain"), glm::dvec2(50, 100));
  EXPECT_EQ(find_window_preset("CT-Lung"), glm::dvec2(-500, 1400));
  EXPECT_EQ(find_window_preset("ct-bone"), glm::dvec2(400, 1000));
  EXPECT_FALSE(find_window_preset("ct-brian"));
  std::vector<std::string> names = window_preset_names();
  EXPECT_EQ(names, (std::vector<std::string>{"ct-bone", "ct-air", "ct-brain", "ct-abdomen",
                                             "ct-lung", "pet", "dti"}));
}

TEST(WindowPresets, EveryPresetInSlicersFileIsThere) {
  const auto file = test::shared_data("slicer-window-level-presets.json");
  SKIP_WITHOUT_SHARED_DATA(file);
  nlohmann::json j = nlohmann::json::parse(std::ifstream(file));
  const auto& presets = j.at("volumeDisplayPresets");
  ASSERT_EQ(presets.size(), window_preset_names().size());
  for (const auto& p : presets) {
    std::optional<glm::dvec2> w = find_window_preset(p.at("name").get<std::string>());
    ASSERT_TRUE(w) << p.at("name");
    EXPECT_EQ(w->x, p.at("level").get<double>());
    EXPECT_EQ(w->y, p.at("window").get<double>());
  }
}

}  // namespace
}  // namespace imx
