#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "intermix/error.hpp"
#include "intermix/metrics.hpp"
#include "test_images.hpp"

namespace imx {
namespace {

TEST(CompareImages, IdenticalImages) {
  Image a = test::structured_image(40, 30);
  ImageComparison c = compare_images(a, a);
  EXPECT_EQ(c.psnr_db, std::numeric_limits<double>::infinity());
  EXPECT_DOUBLE_EQ(c.ssim, 1.0);
  EXPECT_EQ(c.max_error, 0.0);
  EXPECT_EQ(c.frac_over_1, 0.0);
  EXPECT_EQ(c.frac_over_4, 0.0);
  EXPECT_EQ(c.frac_over_16, 0.0);
}

TEST(CompareImages, ErrorFractionsCountCraftedPixels) {
  // 20x10 = 200 pixels: 7 off by 2/255, 5 by 5/255, 3 by 20/255 (in one channel each).
  const float base = 0.5f;
  Image a = test::display_image(20, 10, [&](int, int) { return glm::vec3(base); });
  Image b = test::display_image(20, 10, [&](int x, int y) {
    int i = y * 20 + x;
    glm::vec3 d(base);
    if (i < 7)
      d.g += 2.0f / 255.0f;
    else if (i < 12)
      d.r -= 5.0f / 255.0f;
    else if (i < 15)
      d.b += 20.0f / 255.0f;
    return d;
  });
  ImageComparison c = compare_images(a, b);
  EXPECT_DOUBLE_EQ(c.frac_over_1, 15.0 / 200.0);
  EXPECT_DOUBLE_EQ(c.frac_over_4, 8.0 / 200.0);
  EXPECT_DOUBLE_EQ(c.frac_over_16, 3.0 / 200.0);
  EXPECT_NEAR(c.max_error, 20.0 / 255.0, 1e-6);
  EXPECT_DOUBLE_EQ(c.psnr_db, psnr(a, b));
  EXPECT_DOUBLE_EQ(c.ssim, ssim(a, b));
  EXPECT_LT(c.ssim, 1.0);
}

TEST(CompareImages, SizeMismatchNamesBothSizes) {
  try {
    compare_images(Image(512, 512), Image(256, 256));
    FAIL() << "expected imx::Error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "images differ in size: 512x512 vs 256x256");
  }
}

TEST(CompareImages, EmptyImagesThrow) {
  EXPECT_THROW(compare_images(Image(), Image()), Error);
  EXPECT_THROW(compare_images(Image(), Image(1, 1)), Error);
}

}  // namespace
}  // namespace imx
