// The per-sample formulas on one float (ScalarOps); the lane tests hold the lanes to the same.
#include "volume/sample_formulas.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "volume/sample_ops.hpp"

namespace imx {
namespace {

TEST(SampleFormulas, TrilinearIsExactOnALinearField) {
  // f(x, y, z) = 1 + 2x + 3y + 5z at the corners of the unit cell, in c000, c100, ... order.
  float c[8];
  for (int k = 0; k < 8; ++k)
    c[k] = 1.0f + 2.0f * static_cast<float>(k & 1) + 3.0f * static_cast<float>((k >> 1) & 1) +
           5.0f * static_cast<float>(k >> 2);
  EXPECT_FLOAT_EQ(sample_formulas::trilinear<ScalarOps>(c, 0.25f, 0.5f, 0.75f),
                  1.0f + 0.5f + 1.5f + 3.75f);
  EXPECT_EQ(sample_formulas::trilinear<ScalarOps>(c, 0.0f, 0.0f, 0.0f), c[0]);
  EXPECT_EQ(sample_formulas::trilinear<ScalarOps>(c, 1.0f, 1.0f, 1.0f), c[7]);
}

TEST(SampleFormulas, LightComesFromTheMomentsMeanAndSpread) {
  float centre = 0.0f, spread = 0.0f;
  const float a = 0.8f, mean = 0.25f, sd = 0.1f;
  sample_formulas::light_of<ScalarOps>(a, a * mean, a * (mean * mean + sd * sd), centre, spread);
  EXPECT_NEAR(centre, mean, 1e-6f);
  EXPECT_NEAR(spread, sd, 1e-5f);
  // A mean past the piece's ends is clamped to them; a variance rounded below zero is no spread.
  sample_formulas::light_of<ScalarOps>(a, a * 1.5f, a * 0.9f, centre, spread);
  EXPECT_EQ(centre, 1.0f);
  EXPECT_EQ(spread, 0.0f);
  // A piece without opacity (or a NaN one): the midpoint, no spread.
  for (float none : {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN()}) {
    sample_formulas::light_of<ScalarOps>(none, 0.3f, 0.2f, centre, spread);
    EXPECT_EQ(centre, 0.5f) << none;
    EXPECT_EQ(spread, 0.0f) << none;
  }
}

}  // namespace
}  // namespace imx
