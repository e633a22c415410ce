#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "intermix/error.hpp"
#include "intermix/metrics.hpp"
#include "test_images.hpp"

namespace imx {
namespace {

TEST(Psnr, IdenticalImagesAreInfinite) {
  Image a = test::structured_image(37, 21);
  EXPECT_EQ(psnr(a, a), std::numeric_limits<double>::infinity());
}

TEST(Psnr, UniformDisplayOffset) {
  const float base = 0.25f, d = 0.1f;
  Image a = test::display_image(64, 48, [&](int, int) { return glm::vec3(base); });
  Image b = test::display_image(64, 48, [&](int, int) { return glm::vec3(base + d); });
  // The offset actually seen after the decode/encode round trip, in float.
  double seen = double(srgb_encode(srgb_decode(base + d))) - srgb_encode(srgb_decode(base));
  EXPECT_NEAR(psnr(a, b), -20.0 * std::log10(seen), 1e-6);
  EXPECT_NEAR(psnr(a, b), 20.0, 1e-4);  // -20 log10(0.1)
}

TEST(Psnr, OffsetInOneChannelCountsAsAThird) {
  Image a = test::display_image(16, 16, [](int, int) { return glm::vec3(0.0f); });
  Image b = test::display_image(16, 16, [](int, int) { return glm::vec3(1.0f, 0.0f, 0.0f); });
  EXPECT_NEAR(psnr(a, b), 10.0 * std::log10(3.0), 1e-9);
}

TEST(Psnr, ComparesPixelsCompositedOverBlackAndClamped) {
  // Premultiplied over black: alpha does not change what is seen, and values above 1 clamp.
  Image a(8, 8, glm::vec4(0.2f, 0.4f, 2.0f, 0.5f));
  Image b(8, 8, glm::vec4(0.2f, 0.4f, 1.0f, 1.0f));
  EXPECT_EQ(psnr(a, b), std::numeric_limits<double>::infinity());
}

TEST(Psnr, SizeMismatchThrows) {
  EXPECT_THROW(psnr(Image(4, 4), Image(4, 5)), Error);
  EXPECT_THROW(psnr(Image(), Image()), Error);
}

}  // namespace
}  // namespace imx
