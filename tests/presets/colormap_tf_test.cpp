// Transfer functions from a colour map over a range, with a threshold and a symmetric form,
// checked against the rule in presets/colormap_tf.hpp computed here from the maps' definitions.
#include <gtest/gtest.h>

#include <cmath>

#include "intermix/error.hpp"
#include "presets/colormap.hpp"
#include "presets/colormap_tf.hpp"
#include "volume/tf_lut.hpp"

namespace imx {
namespace {

float linear(float srgb) {
  return srgb <= 0.04045f ? srgb / 12.92f : std::pow((srgb + 0.055f) / 1.055f, 2.4f);
}

void expect_rgba(const glm::vec4& got, const glm::vec3& rgb, float a, const char* what, double v) {
  EXPECT_NEAR(got.r, rgb.r, 2e-5) << what << " at " << v;
  EXPECT_NEAR(got.g, rgb.g, 2e-5) << what << " at " << v;
  EXPECT_NEAR(got.b, rgb.b, 2e-5) << what << " at " << v;
  EXPECT_NEAR(got.a, a, 2e-5) << what << " at " << v;
}

TEST(ColormapTransferFunction, ColourAndOpacityFollowTheRange) {
  ColormapTransferFunction c;
  c.map = Colormap::inferno;
  c.lo = 3.0;
  c.hi = 8.0;
  const TransferFunction tf = colormap_transfer_function(c);
  for (int k = 0; k <= 997; ++k) {
    const double v = 2.0 + 7.0 * k / 997.0;
    const double s = std::clamp((v - 3.0) / 5.0, 0.0, 1.0);
    expect_rgba(evaluate_transfer_function(tf, v), colormap_rgb(c.map, static_cast<float>(s)),
                static_cast<float>(s), "inferno", v);
  }
}

TEST(ColormapTransferFunction, ThresholdHidesBelowItAndOpacityScales) {
  ColormapTransferFunction c;
  c.map = Colormap::hot;
  c.lo = 3.0;
  c.hi = 8.0;
  c.threshold = 4.0;
  c.opacity = 0.5f;
  const TransferFunction tf = colormap_transfer_function(c);
  EXPECT_EQ(evaluate_transfer_function(tf, 3.999).a, 0.0f);
  EXPECT_EQ(evaluate_transfer_function(tf, -100.0).a, 0.0f);
  expect_rgba(evaluate_transfer_function(tf, 4.0), colormap_rgb(c.map, 0.2f), 0.5f * 0.2f, "step",
              4.0);
  expect_rgba(evaluate_transfer_function(tf, 6.5), colormap_rgb(c.map, 0.7f), 0.5f * 0.7f, "in",
              6.5);
  expect_rgba(evaluate_transfer_function(tf, 50.0), glm::vec3(1.0f), 0.5f, "above", 50.0);
}

// cold-hot, symmetric: +|v| in red-yellow (1, s, 0), -|v| in blue-lightblue (0, s, 1), display
// values, from red / blue next to the threshold to yellow / light blue at the range's end.
TEST(ColormapTransferFunction, SymmetricColdHotShowsNegativesInTheColdHalf) {
  ColormapTransferFunction c;
  c.map = Colormap::cold_hot;
  c.lo = 3.0;
  c.hi = 8.0;
  c.threshold = 3.0;
  c.symmetric = true;
  const TransferFunction tf = colormap_transfer_function(c);
  for (int k = 0; k <= 127; ++k) {
    const double s = k / 127.0;  // the half's entries
    const double m = 3.0 + 5.0 * s;
    const float sf = linear(static_cast<float>(s));
    expect_rgba(evaluate_transfer_function(tf, m), {1.0f, sf, 0.0f}, static_cast<float>(s), "hot",
                m);
    expect_rgba(evaluate_transfer_function(tf, -m), {0.0f, sf, 1.0f}, static_cast<float>(s), "cold",
                -m);
  }
  for (double v : {-2.999, -1.0, 0.0, 1.5, 2.999})
    EXPECT_EQ(evaluate_transfer_function(tf, v).a, 0.0f);
}

TEST(ColormapTransferFunction, SymmetricMirrorsOtherMapsAndShowsAtMinusThreshold) {
  ColormapTransferFunction c;
  c.map = Colormap::viridis;
  c.lo = 2.0;
  c.hi = 6.0;
  c.threshold = 3.0;
  c.symmetric = true;
  const TransferFunction tf = colormap_transfer_function(c);
  for (double m : {3.0, 3.3, 4.0, 5.99, 6.0, 9.0}) {
    const glm::vec4 pos = evaluate_transfer_function(tf, m);
    const double s = std::min((m - 2.0) / 4.0, 1.0);
    expect_rgba(pos, colormap_rgb(c.map, static_cast<float>(s)), static_cast<float>(s), "+", m);
    expect_rgba(evaluate_transfer_function(tf, -m), glm::vec3(pos), pos.a, "-", -m);
  }
  EXPECT_EQ(evaluate_transfer_function(tf, -2.99).a, 0.0f);
  EXPECT_EQ(evaluate_transfer_function(tf, 2.99).a, 0.0f);
  // Sorted points, as every renderer's LUT needs.
  for (size_t i = 1; i < tf.points.size(); ++i)
    EXPECT_LE(tf.points[i - 1].value, tf.points[i].value) << i;
  EXPECT_NO_THROW(TfLut{tf});
}

TEST(ColormapTransferFunction, RefusesContradictoryFields) {
  ColormapTransferFunction c;
  c.lo = 5.0;
  c.hi = 5.0;
  EXPECT_THROW(colormap_transfer_function(c), Error);
  c.hi = 8.0;
  c.threshold = 9.0;
  EXPECT_THROW(colormap_transfer_function(c), Error);
  c.threshold = -1.0;
  c.symmetric = true;
  EXPECT_THROW(colormap_transfer_function(c), Error);
  c.threshold.reset();
  c.lo = -1.0;
  EXPECT_THROW(colormap_transfer_function(c), Error);
  c.lo = 0.0;
  c.opacity = 1.5f;
  EXPECT_THROW(colormap_transfer_function(c), Error);
  c.opacity = std::nanf("");
  EXPECT_THROW(colormap_transfer_function(c), Error);
}

}  // namespace
}  // namespace imx
