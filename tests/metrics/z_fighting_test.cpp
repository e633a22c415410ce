#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "intermix/error.hpp"
#include "metrics/z_fighting.hpp"

namespace imx {
namespace {

TEST(ZFighting, UniformRegionHasNoSpreadNorChange) {
  Image a(16, 16, glm::vec4(0.3f, 0.2f, 0.1f, 1.0f));
  std::vector<uint8_t> region(a.size(), 1);
  ZFightingStats s = z_fighting(a, a, region);
  EXPECT_EQ(s.pixels, 256);
  EXPECT_NEAR(s.std_dev, 0.0, 1e-9);
  EXPECT_NEAR(s.speckle, 0.0, 1e-9);
  EXPECT_NEAR(s.jitter_change, 0.0, 1e-9);
}

TEST(ZFighting, SpeckleIsNoiseAndAGradientIsNot) {
  Image ramp(32, 32), noisy(32, 32), flipped(32, 32);
  std::mt19937 gen(1);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      ramp.at(x, y) = glm::vec4(0.2f + 0.01f * x, 0.3f, 0.3f, 1.0f);
      bool red = gen() % 2;  // two colours picked at random: z-fighting
      noisy.at(x, y) = red ? glm::vec4(0.8f, 0.1f, 0.1f, 1) : glm::vec4(0.1f, 0.8f, 0.1f, 1);
      flipped.at(x, y) = red ? noisy.at(x, y) : glm::vec4(0.8f, 0.1f, 0.1f, 1);
    }
  std::vector<uint8_t> region(ramp.size(), 0);
  for (int y = 4; y < 28; ++y)
    for (int x = 4; x < 28; ++x) region[y * 32 + x] = 1;
  ZFightingStats r = z_fighting(ramp, ramp, region);
  EXPECT_GT(r.std_dev, 5.0 / 255.0);
  EXPECT_LT(r.speckle, 0.01 / 255.0);
  ZFightingStats n = z_fighting(noisy, flipped, region);
  EXPECT_GT(n.speckle, 50.0 / 255.0);
  EXPECT_GT(n.jitter_change, 50.0 / 255.0);
  EXPECT_EQ(n.pixels, 24 * 24);
}

TEST(ZFighting, RejectsMismatchedSizes) {
  Image a(4, 4), b(4, 5);
  std::vector<uint8_t> region(16, 1);
  EXPECT_THROW(z_fighting(a, b, region), Error);
  EXPECT_THROW(z_fighting(a, a, std::span<const uint8_t>(region).first(8)), Error);
}

}  // namespace
}  // namespace imx
