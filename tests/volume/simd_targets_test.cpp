#include "volume/simd_targets.hpp"

#include <gtest/gtest.h>

#include <map>

#include "expect_error.hpp"
#include "intermix/error.hpp"

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

}  // namespace
}  // namespace imx
