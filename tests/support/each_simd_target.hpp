// Runs a check once on every SIMD target this build compiled the lane kernels for and this
// machine runs (Highway's per-target test pattern, through the dispatcher), each traced by name.
#pragma once
#include <gtest/gtest.h>

#include <string>

#include "volume/simd_targets.hpp"

namespace imx::test {

template <class Check>
void for_each_simd_target(Check check) {
  for (const std::string& target : simd_targets()) {
    SCOPED_TRACE("SIMD target " + target);
    limit_simd_target(target);
    check(target);
  }
  limit_simd_target("");
}

}  // namespace imx::test
