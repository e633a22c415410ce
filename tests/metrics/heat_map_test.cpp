#include <gtest/gtest.h>

#include "intermix/error.hpp"
#include "intermix/metrics.hpp"
#include "test_images.hpp"

namespace imx {
namespace {

TEST(ErrorHeatMap, BlackWhereEqualAndColouredWhereDifferent) {
  Image a = test::structured_image(16, 12);
  Image b = a;
  b.at(3, 4) = test::from_display(glm::vec3(srgb_encode(a.at(3, 4).r) + 0.02f,
                                            srgb_encode(a.at(3, 4).g), srgb_encode(a.at(3, 4).b)));
  b.at(10, 7) = glm::vec4(1.0f) - a.at(10, 7) + glm::vec4(0, 0, 0, 1);
  Image heat = error_heat_map(a, b);
  ASSERT_EQ(heat.width(), 16);
  ASSERT_EQ(heat.height(), 12);
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 16; ++x) {
      glm::vec4 h = heat.at(x, y);
      EXPECT_EQ(h.a, 1.0f);
      bool changed = (x == 3 && y == 4) || (x == 10 && y == 7);
      if (changed)
        EXPECT_GT(h.r, 0.0f) << x << "," << y;
      else
        EXPECT_EQ(h, glm::vec4(0, 0, 0, 1)) << x << "," << y;
    }
  // An error of 0.02 x 16 = 0.32 heat is still in the red third; the large one saturates to white.
  EXPECT_EQ(heat.at(3, 4).g, 0.0f);
  EXPECT_EQ(heat.at(10, 7), glm::vec4(1.0f));
}

TEST(ErrorHeatMap, IsLinearSoDisplayHeatRoundTrips) {
  Image a(1, 1, glm::vec4(0, 0, 0, 1));
  Image b = test::display_image(1, 1, [](int, int) { return glm::vec3(0.1f, 0, 0); });
  // Error 0.1 at scale 5 is heat 0.5: display (1, 0.5, 0), stored linear.
  glm::vec4 h = error_heat_map(a, b, 5.0).at(0, 0);
  EXPECT_NEAR(srgb_encode(h.r), 1.0f, 1e-6);
  EXPECT_NEAR(srgb_encode(h.g), 0.5f, 1e-5);
  EXPECT_EQ(h.b, 0.0f);
}

TEST(ErrorHeatMap, RejectsBadInput) {
  EXPECT_THROW(error_heat_map(Image(4, 4), Image(5, 4)), Error);
  EXPECT_THROW(error_heat_map(Image(4, 4), Image(4, 4), 0.0), Error);
}

}  // namespace
}  // namespace imx
