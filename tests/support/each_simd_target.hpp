// Runs a check once on every SIMD target this build compiled the lane kernels for and this
// machine runs (Highway's per-target test pattern, through the dispatcher), each traced by name.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "volume/simd_targets.hpp"

namespace imx::test {

// At the end the limit is IMX_SIMD's again, so that the rest of the program keeps to it.
template <class Check>
void for_each_simd_target(Check check) {
  for (const std::string& target : simd_targets()) {
    SCOPED_TRACE("SIMD target " + target);
    limit_simd_target(target);
    EXPECT_EQ(simd_target(), target);
    check(target);
  }
  const char* env = std::getenv("IMX_SIMD");
  limit_simd_target(env ? env : "");
}

}  // namespace imx::test
