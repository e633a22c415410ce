#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "presets/colormap.hpp"

namespace imx {
namespace {

float linear(float srgb) {
  return srgb <= 0.04045f ? srgb / 12.92f : std::pow((srgb + 0.055f) / 1.055f, 2.4f);
}

// Grey is the display grey of the windowed value (docs/colour.md): t shows as t * 255.
TEST(Colormap, GreyIsTheDisplayGreyOfTheWindowedValue) {
  for (float t : {0.0f, 0.1f, 0.5f, 0.999f, 1.0f})
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(colormap_rgb(Colormap::grey, t)[c], linear(t), 1e-6);
  EXPECT_EQ(colormap_rgb(Colormap::grey, -1.0f), glm::vec3(0.0f));
  EXPECT_EQ(colormap_rgb(Colormap::grey, 2.0f), glm::vec3(1.0f));
}

// matplotlib's published end colours (sRGB), decoded to intermix's linear RGB.
TEST(Colormap, EndsAreMatplotlibsColoursInLinearRgb) {
  const glm::vec3 viridis0 = colormap_rgb(Colormap::viridis, 0.0f);
  EXPECT_NEAR(viridis0.r, linear(0.267004f), 1e-6);
  EXPECT_NEAR(viridis0.g, linear(0.004874f), 1e-6);
  EXPECT_NEAR(viridis0.b, linear(0.329415f), 1e-6);
  const glm::vec3 viridis1 = colormap_rgb(Colormap::viridis, 1.0f);
  EXPECT_NEAR(viridis1.r, linear(0.993248f), 1e-6);
  EXPECT_NEAR(viridis1.g, linear(0.906157f), 1e-6);
  EXPECT_NEAR(viridis1.b, linear(0.143936f), 1e-6);
  const glm::vec3 inferno0 = colormap_rgb(Colormap::inferno, 0.0f);
  EXPECT_NEAR(inferno0.r, linear(0.001462f), 1e-6);
  EXPECT_NEAR(inferno0.b, linear(0.013866f), 1e-6);
  const glm::vec3 inferno1 = colormap_rgb(Colormap::inferno, 1.0f);
  EXPECT_NEAR(inferno1.r, linear(0.988362f), 1e-6);
  EXPECT_NEAR(inferno1.g, linear(0.998364f), 1e-6);
  EXPECT_NEAR(inferno1.b, linear(0.644924f), 1e-6);
  EXPECT_EQ(colormap_rgb(Colormap::hot, 1.0f), glm::vec3(1.0f));
  const glm::vec3 hot0 = colormap_rgb(Colormap::hot, 0.0f);
  EXPECT_NEAR(hot0.r, linear(0.0416f), 1e-6);
  EXPECT_EQ(hot0.g, 0.0f);
}

TEST(Colormap, InterpolatesBetweenEntriesAndClamps) {
  const auto& e = detail::kViridis;
  const float t = (100.0f + 0.25f) / 255.0f;
  const glm::vec3 c = colormap_rgb(Colormap::viridis, t);
  EXPECT_NEAR(c.g, e[100].g + 0.25f * (e[101].g - e[100].g), 1e-6);
  EXPECT_EQ(colormap_rgb(Colormap::inferno, -3.0f), colormap_rgb(Colormap::inferno, 0.0f));
  EXPECT_EQ(colormap_rgb(Colormap::inferno, 7.0f), colormap_rgb(Colormap::inferno, 1.0f));
  EXPECT_EQ(colormap_rgb(Colormap::hot, std::numeric_limits<float>::quiet_NaN()),
            colormap_rgb(Colormap::hot, 0.0f));
}

// Perceptual maps get brighter all the way: luminance rises with t.
TEST(Colormap, ViridisAndInfernoLuminanceRisesMonotonically) {
  for (Colormap m : {Colormap::viridis, Colormap::inferno, Colormap::hot}) {
    float previous = -1.0f;
    for (int i = 0; i <= 1000; ++i) {
      glm::vec3 c = colormap_rgb(m, static_cast<float>(i) / 1000.0f);
      float y = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
      EXPECT_GE(y, previous) << static_cast<int>(m) << " at " << i;
      previous = y;
    }
  }
}

// The overlay maps from their defining formulas (display values): red-yellow (1, t, 0),
// blue-lightblue (0, t, 1), cold-hot the second reversed below t = 0.5 and the first above.
TEST(Colormap, OverlayMapsFollowTheirFormulas) {
  for (int i = 0; i < 256; ++i) {
    const float t = static_cast<float>(i) / 255.0f;
    const glm::vec3 ry = colormap_rgb(Colormap::red_yellow, t);
    EXPECT_NEAR(ry.r, 1.0f, 1e-6);
    EXPECT_NEAR(ry.g, linear(t), 1e-5) << i;
    EXPECT_EQ(ry.b, 0.0f);
    const glm::vec3 bl = colormap_rgb(Colormap::blue_lightblue, t);
    EXPECT_EQ(bl.r, 0.0f);
    EXPECT_NEAR(bl.g, linear(t), 1e-5) << i;
    EXPECT_NEAR(bl.b, 1.0f, 1e-6);
    const glm::vec3 ch = colormap_rgb(Colormap::cold_hot, t);
    if (i < 128)
      EXPECT_NEAR(ch.g, linear(static_cast<float>(127 - i) / 127.0f), 1e-5) << i;
    else
      EXPECT_NEAR(ch.g, linear(static_cast<float>(i - 128) / 127.0f), 1e-5) << i;
    EXPECT_EQ(ch.r, i < 128 ? 0.0f : 1.0f) << i;
  }
}

// matplotlib's plasma and jet ends (display values), and every name finds its map.
TEST(Colormap, PlasmaAndJetEndsAndNames) {
  const glm::vec3 plasma0 = colormap_rgb(Colormap::plasma, 0.0f);
  EXPECT_NEAR(plasma0.r, linear(0.050383f), 1e-6);
  EXPECT_NEAR(plasma0.b, linear(0.527975f), 1e-6);
  const glm::vec3 plasma1 = colormap_rgb(Colormap::plasma, 1.0f);
  EXPECT_NEAR(plasma1.g, linear(0.975158f), 1e-6);
  EXPECT_NEAR(colormap_rgb(Colormap::jet, 0.0f).b, linear(0.5f), 1e-6);  // dark blue
  EXPECT_NEAR(colormap_rgb(Colormap::jet, 1.0f).r, linear(0.5f), 1e-6);  // dark red
  EXPECT_EQ(colormap_rgb(Colormap::jet, 0.0f).r, 0.0f);
  for (size_t i = 0; i < kColormapNames.size(); ++i)
    EXPECT_EQ(find_colormap(kColormapNames[i]), static_cast<Colormap>(i));
  EXPECT_EQ(find_colormap("gray"), std::nullopt);
  EXPECT_TRUE(colormap_is_diverging(Colormap::cold_hot));
  EXPECT_FALSE(colormap_is_diverging(Colormap::hot));
}

}  // namespace
}  // namespace imx
