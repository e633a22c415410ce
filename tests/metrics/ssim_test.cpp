#include <cmath>

#include <gtest/gtest.h>

#include "intermix/error.hpp"
#include "intermix/metrics.hpp"
#include "test_images.hpp"

namespace imx {
namespace {

TEST(Ssim, IdenticalImagesScoreOne) {
  Image a = test::structured_image(67, 45);
  EXPECT_DOUBLE_EQ(ssim(a, a), 1.0);
}

TEST(Ssim, DecreasesWithMoreNoise) {
  Image a = test::structured_image(64, 64);
  double little = ssim(a, test::noisy_copy(a, 0.02f));
  double more = ssim(a, test::noisy_copy(a, 0.1f));
  double most = ssim(a, test::noisy_copy(a, 0.3f));
  EXPECT_LT(little, 1.0);
  EXPECT_LT(more, little);
  EXPECT_LT(most, more);
  EXPECT_GT(most, -1.0);
}

TEST(Ssim, IsSymmetric) {
  Image a = test::structured_image(53, 40);
  Image b = test::noisy_copy(a, 0.1f);
  EXPECT_DOUBLE_EQ(ssim(a, b), ssim(b, a));
}

TEST(Ssim, SeesAChangeInTheLastColumnsTheStrideSkips) {
  // Width 14: windows at x = 0, 4 cover up to column 11; the edge window must reach 13.
  Image a = test::structured_image(14, 8);
  Image b = a;
  for (int y = 0; y < 8; ++y) b.at(13, y) = glm::vec4(1.0f);
  EXPECT_LT(ssim(a, b), 1.0);
}

TEST(Ssim, ImageSmallerThanTheWindowUsesOneWindow) {
  Image a = test::structured_image(5, 3);
  EXPECT_DOUBLE_EQ(ssim(a, a), 1.0);
  double s = ssim(a, test::noisy_copy(a, 0.2f));
  EXPECT_TRUE(std::isfinite(s));
  EXPECT_LT(s, 1.0);
}

TEST(Ssim, SizeMismatchThrows) {
  EXPECT_THROW(ssim(Image(8, 8), Image(9, 8)), Error);
}

}  // namespace
}  // namespace imx
