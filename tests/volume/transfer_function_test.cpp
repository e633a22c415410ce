#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "intermix/error.hpp"
#include "volume/tf_lut.hpp"

namespace imx {
namespace {

TransferFunction ramp() {
  TransferFunction tf;
  tf.points = {{-1000.0, {0, 0, 0, 0}}, {300.0, {1, 0.5f, 0.25f, 0.2f}}, {700.0, {1, 1, 1, 0.8f}}};
  return tf;
}

TEST(TransferFunction, LutMatchesThePiecewiseLinearFunction) {
  TransferFunction tf = ramp();
  TfLut lut(tf);
  EXPECT_NEAR(lut.lookup(-2000).a, 0.0f, 1e-6f);  // constant below the first point
  EXPECT_NEAR(lut.lookup(5000).a, 0.8f, 1e-6f);   // and above the last
  EXPECT_NEAR(lut.lookup(300).r, 1.0f, 2e-3f);
  EXPECT_NEAR(lut.lookup(500).a, 0.5f, 2e-3f);
  EXPECT_NEAR(lut.lookup(500).g, 0.75f, 2e-3f);
  EXPECT_NEAR(lut.lookup(-350).a, 0.1f, 2e-3f);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1200, 900);
  for (int i = 0; i < 1000; ++i) {
    double v = u(rng);
    glm::vec4 exact = evaluate_transfer_function(tf, v);
    glm::vec4 baked = lut.lookup(static_cast<float>(v));
    for (int c = 0; c < 4; ++c) ASSERT_NEAR(baked[c], exact[c], 2e-3f) << v;
  }
  EXPECT_FLOAT_EQ(lut.max_opacity(), 0.8f);
}

TEST(TransferFunction, RejectsBadPoints) {
  TransferFunction tf = ramp();
  tf.points[1].value = -2000;  // unsorted
  EXPECT_THROW(TfLut{tf}, Error);
  tf = ramp();
  tf.points[2].rgba.a = 1.5f;
  EXPECT_THROW(TfLut{tf}, Error);
  EXPECT_THROW(TfLut{TransferFunction{}}, Error);
}

TEST(OpacityCorrection, MatchesTheClosedForm) {
  // Two half steps must absorb exactly what one full step absorbs.
  float a = 0.6f;
  float half = correct_opacity(a, 0.5f, 1.0f);
  EXPECT_NEAR(1.0f - (1.0f - half) * (1.0f - half), a, 1e-6f);
  EXPECT_NEAR(correct_opacity(a, 1.0f, 1.0f), a, 1e-7f);
  EXPECT_NEAR(correct_opacity(0.5f, 2.0f, 1.0f), 0.75f, 1e-6f);
  EXPECT_NEAR(correct_opacity(0.19f, 0.25f, 0.5f), 1.0f - std::sqrt(0.81f), 1e-6f);
  EXPECT_EQ(correct_opacity(0.0f, 3.0f, 1.0f), 0.0f);
  EXPECT_EQ(correct_opacity(1.0f, 0.1f, 1.0f), 1.0f);
}

}  // namespace
}  // namespace imx

namespace imx {
namespace {

TEST(TransferFunction, NonFiniteAndExtremeValuesReadTheEndEntries) {
  TfLut lut(ramp());
  EXPECT_EQ(lut.lookup(std::numeric_limits<float>::quiet_NaN()), lut.entries().front());
  EXPECT_EQ(lut.lookup(-std::numeric_limits<float>::max()), lut.entries().front());
  EXPECT_EQ(lut.lookup(std::numeric_limits<float>::max()), lut.entries().back());
  EXPECT_EQ(lut.lookup(std::numeric_limits<float>::infinity()), lut.entries().back());
  // The exact evaluator too: a NaN gives the first point instead of reading past the last.
  EXPECT_EQ(evaluate_transfer_function(ramp(), std::numeric_limits<double>::quiet_NaN()),
            ramp().points.front().rgba);
}

TEST(TransferFunction, ASpanWiderThanAFloatIsRefused) {
  TransferFunction tf;
  tf.points = {{-3e38, {0, 0, 0, 0}}, {3e38, {1, 1, 1, 1}}};
  try {
    TfLut lut(tf);
    ADD_FAILURE() << "a span of 6e38 should be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("wider than a float"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace imx
