// The intersection band and the PSNR restricted to it.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "intermix/band_metrics.hpp"
#include "intermix/error.hpp"
#include "intermix/metrics.hpp"

namespace imx {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

TEST(IntersectionBand, FollowsTheCrossingOfTwoDepthRamps) {
  // a is at depth 10 everywhere but the last column; b is nearer left of x = 8
  Image a(16, 8, glm::vec4(10.0f, 0, 0, 1)), b(16, 8, glm::vec4(kInf, 0, 0, 1));
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) {
      b.at(x, y).r = x < 8 ? 5.0f : 15.0f;
      if (x == 15) a.at(x, y).r = kInf;  // only b there: a silhouette, not an intersection
    }
  std::vector<uint8_t> band = intersection_band(a, b, 1);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x)
      EXPECT_EQ(band[y * 16 + x], x >= 6 && x <= 8 ? 1 : 0) << x << "," << y;
  EXPECT_EQ(intersection_band(a, b, 0)[3 * 16 + 7], 1);
  EXPECT_EQ(intersection_band(a, b, 0)[3 * 16 + 8], 0);
}

TEST(IntersectionBand, MaskedPsnrCountsOnlyTheMask) {
  Image a(4, 1, glm::vec4(0.5f, 0.5f, 0.5f, 1)), b = a;
  b.at(3, 0) = glm::vec4(1.0f);  // an error outside the mask
  std::vector<uint8_t> mask = {1, 1, 0, 0};
  EXPECT_EQ(masked_psnr(a, b, mask), std::numeric_limits<double>::infinity());
  mask[3] = 1;
  // the same error over 3 pixels instead of 4
  EXPECT_NEAR(masked_psnr(a, b, mask), psnr(a, b) - 10.0 * std::log10(4.0 / 3.0), 1e-6);
  EXPECT_TRUE(std::isnan(masked_psnr(a, b, std::vector<uint8_t>(4, 0))));
  EXPECT_THROW(masked_psnr(a, b, std::vector<uint8_t>(3, 1)), Error);
}

}  // namespace
}  // namespace imx
