#include "volume/simd_targets.hpp"

#include <gtest/gtest.h>

#include <map>

#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "volume/wide_scalar.hpp"

namespace imx {
namespace {

// Each target this machine runs can be chosen, and the kernels then run with its lanes: 16 for
// AVX-512, 8 for AVX2, 4 for the 128-bit targets, 1 for the scalar fallback.
TEST(SimdTargets, EachTargetCanBeChosenAndRunsWithItsLanes) {
  const std::map<std::string, int> lanes = {{"AVX3", 16}, {"AVX3_DL", 16}, {"AVX2", 8},
                                            {"SSE4", 4},  {"EMU128", 4},   {"NEON", 4},
                                            {"SCALAR", 1}};
  const std::vector<std::string> targets = simd_targets();
  ASSERT_FALSE(targets.empty());
  // The lowest target is the portable one, which runs on any CPU of the architecture.
  EXPECT_TRUE(targets.back() == "SCALAR" || targets.back() == "EMU128") << targets.back();
  for (const std::string& t : targets) {
    limit_simd_target(t);
    EXPECT_EQ(simd_target(), t);
    if (lanes.count(t)) {
      EXPECT_EQ(simd_lanes(), lanes.at(t)) << t;
    }
  }
  limit_simd_target("Lowest");
  EXPECT_EQ(simd_target(), targets.back());
  limit_simd_target("");
  EXPECT_EQ(simd_target(), targets.front());  // the widest, once the limit is lifted
}

TEST(SimdTargets, AnUnknownTargetIsNamedInTheError) {
  const std::string message = test::error_of([] { limit_simd_target("avx9000"); });
  EXPECT_NE(message.find("avx9000"), std::string::npos) << message;
  EXPECT_NE(message.find(simd_targets().front()), std::string::npos) << message;
  EXPECT_EQ(simd_target(), simd_targets().front());  // no limit was left behind
}

// The scalar kernels' wide copy follows the same limit: it runs exactly where an AVX2-or-wider
// target is allowed, so IMX_SIMD=lowest runs every baseline copy.
TEST(SimdTargets, TheScalarKernelsWideCopyFollowsTheLimit) {
  for (const std::string& t : simd_targets()) {
    limit_simd_target(t);
    const bool wide = t == "AVX2" || t.starts_with("AVX3");
    EXPECT_EQ(wide_scalar_available(), wide) << t;
  }
  limit_simd_target("");
}

// Both copies compute the body: the same results, fused or not, within a rounding.
TEST(SimdTargets, BothCopiesOfAKernelBodyRunIt) {
  volatile float a = 1.0f / 3.0f, b = 3.0f, c = -1.0f;
  for (bool wide : {false, true}) {
    if (wide && !wide_scalar_available()) continue;
    int calls = 0;
    const float r = run_wide_scalar(wide, [&] {
      ++calls;
      return a * b + c;
    });
    EXPECT_EQ(calls, 1);
    EXPECT_NEAR(r, 0.0f, 1e-7f) << wide;
  }
}

}  // namespace
}  // namespace imx
