#include "core/blinn_phong.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace imx {
namespace {

// The squaring path must agree with std::pow (rounding grows with the squarings: 4e-5 relative
// at n = 1024, far below one 8-bit level) wherever the result can show, for whole and
// fractional exponents alike, and never produce a denormal.
TEST(SpecularPower, MatchesStdPow) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> base(0.0f, 1.0f);
  for (float n : {0.0f, 1.0f, 2.0f, 7.0f, 24.0f, 32.0f, 100.0f, 1024.0f, 0.5f, 12.5f, 2000.0f}) {
    for (int k = 0; k < 2000; ++k) {
      float x = k == 0 ? 1.0f : k == 1 ? 0.0f : base(rng);
      float expected = std::pow(x, n), got = specular_power(x, n);
      EXPECT_NEAR(got, expected, 4e-5f * expected + 1e-12f) << x << "^" << n;
      EXPECT_NE(std::fpclassify(got), FP_SUBNORMAL) << x << "^" << n;
    }
  }
}

}  // namespace
}  // namespace imx
