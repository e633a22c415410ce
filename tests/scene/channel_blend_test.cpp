// Channels blended into one colour volume: their windowed colours summed or the largest.
#include <gtest/gtest.h>

#include "intermix/error.hpp"
#include "scene/channel_blend.hpp"

namespace imx {
namespace {

VolumeData grid(std::vector<uint16_t> values) {
  VolumeData v;
  v.dims = glm::ivec3(static_cast<int>(values.size()), 1, 1);
  v.voxels = VoxelBuffer<uint16_t>(std::move(values));
  return v;
}

TEST(ChannelBlend, AddSumsAndMaxTakesTheLargestInLinearLight) {
  detail::OmeChannel grey;
  grey.srgb = glm::vec3(0.5f);  // linear 0.214
  grey.window = glm::dvec2(50.0, 100.0);
  const std::vector<VolumeData> grids = {grid({40, 100, 100, 75}), grid({0, 0, 100, 75})};
  const std::vector<detail::OmeChannel> looks = {grey, grey};
  const VolumeData add = blend_channels(grids, looks, ChannelBlend::add, "x");
  const VolumeData max = blend_channels(grids, looks, ChannelBlend::max, "x");
  ASSERT_TRUE(add.colours && max.colours);
  EXPECT_EQ(add.type(), VoxelType::u8);
  const auto red = [](const VolumeData& v, int i) { return v.colours->rgb[3 * i]; };
  // Below both windows: nothing, neither colour nor opacity.
  EXPECT_EQ(red(add, 0), 0);
  EXPECT_EQ(add.value_at(0, 0, 0), 0.0);
  // One channel at its window's end: its colour, sRGB 0.5, either way.
  EXPECT_EQ(red(add, 1), 128);
  EXPECT_EQ(red(max, 1), 128);
  EXPECT_EQ(max.value_at(1, 0, 0), 255.0);
  // Both at their ends: the sum is linear 0.428 (sRGB 0.69), the maximum stays 0.214.
  EXPECT_NEAR(red(add, 2), 175, 1);
  EXPECT_EQ(red(max, 2), 128);
  // Both half way: scalars 0.5 + 0.5 = 1 added, 0.5 the largest.
  EXPECT_EQ(add.value_at(3, 0, 0), 255.0);
  EXPECT_NEAR(max.value_at(3, 0, 0), 128.0, 1.0);
  EXPECT_THROW(blend_channels(std::vector<VolumeData>{grid({1, 2}), grid({1})}, looks,
                              ChannelBlend::add, "x"),
               Error);
}

}  // namespace
}  // namespace imx
