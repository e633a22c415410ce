#include "core/specular_table.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace imx {
namespace {

// Every exponent, from a dull 1 to a mirror-like 10000, within 1e-4 of x^n over all of [0, 1]
// (absolute: specular coefficients are at most 1, so this is far below one 8-bit step).
TEST(SpecularTable, MatchesPowForEveryShininess) {
  for (float n : {1.0f, 2.0f, 8.0f, 32.0f, 33.5f, 128.0f, 1000.0f, 10000.0f}) {
    SpecularTable table(n);
    for (int i = 0; i <= 100000; ++i) {
      float x = static_cast<float>(i) / 100000.0f;
      ASSERT_NEAR(table(x), std::pow(x, n), 1e-4f) << "n = " << n << ", x = " << x;
    }
    EXPECT_FLOAT_EQ(table(1.0f), 1.0f) << n;
  }
}

TEST(SpecularTable, ExponentsBelowOneAreExact) {
  for (float n : {0.0f, 0.25f, 0.5f}) {
    SpecularTable table(n);
    for (float x : {0.0f, 1e-6f, 0.01f, 0.3f, 1.0f}) EXPECT_FLOAT_EQ(table(x), std::pow(x, n));
  }
}

TEST(SpecularTable, OutOfRangeInputsAreClamped) {
  SpecularTable table(32.0f);
  EXPECT_EQ(table(-0.5f), 0.0f);
  EXPECT_EQ(table(std::nanf("")), 0.0f);
  EXPECT_FLOAT_EQ(table(1.5f), 1.0f);
}

}  // namespace
}  // namespace imx
