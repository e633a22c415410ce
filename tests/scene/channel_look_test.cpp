// An OME channel's look: a ramp in its colour, decoded from sRGB, over its window.
#include <gtest/gtest.h>

#include "core/colour.hpp"
#include "scene/channel_look.hpp"

namespace imx {
namespace {

TEST(ChannelLook, RampsInTheChannelsDisplayColourOverTheWindow) {
  detail::OmeChannel c;
  c.label = "GFP";
  c.srgb = glm::vec3(1.0f, 0.5f, 0.0f);
  c.window = glm::dvec2(100.0, 900.0);
  VolumeData data;
  data.dims = glm::ivec3(2, 1, 1);
  data.voxels = VoxelBuffer<uint16_t>(std::vector<uint16_t>{0, 4000});
  const AutomaticLook look = channel_look(c, data);
  const nlohmann::json& p = look.transfer_function["points"];
  ASSERT_EQ(p.size(), 2u);
  // Transparent at the window's start: a voxel below it adds nothing.
  EXPECT_EQ(p[0][0], 100.0);
  EXPECT_EQ(p[0][4], 0.0);
  EXPECT_EQ(p[1][0], 900.0);
  EXPECT_GT(p[1][4].get<double>(), 0.0);
  // The channel's display colour as OME gives it: scene files' points are display colours,
  // decoded by the loader once (docs/colour.md), so decoding here would darken it twice.
  EXPECT_EQ(p[1][1], 1.0);
  EXPECT_EQ(p[1][2], 0.5);
  EXPECT_EQ(p[1][3], 0.0);
  EXPECT_NE(look.reason.find("GFP"), std::string::npos);
  // No window: the voxels' range.
  c.window.reset();
  const AutomaticLook whole = channel_look(c, data);
  EXPECT_EQ(whole.transfer_function["points"][0][0], 0.0);
  EXPECT_EQ(whole.transfer_function["points"][1][0], 4000.0);
}

}  // namespace
}  // namespace imx
