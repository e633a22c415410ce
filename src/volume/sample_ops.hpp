// ScalarOps: the per-sample arithmetic vocabulary on one float. sample_formulas.hpp writes each
// per-sample formula once against this vocabulary; the lane kernels instantiate the same
// formulas with LaneOps (lanes-inl.hpp: the same names on Highway vectors, one ray per lane).
// Pure: no allocation, no exceptions, no globals.
#pragma once
#include <cmath>

namespace imx {

struct ScalarOps {
  using V = float;
  using M = bool;

  static V splat(float x) { return x; }
  static V sub(V a, V b) { return a - b; }
  static V mul(V a, V b) { return a * b; }
  static V div(V a, V b) { return a / b; }
  // a * b + c, unfused unless the compiler contracts it (a fused multiply-add is a library call
  // on the baseline x86-64 target); lanes fuse it where the target has FMA.
  static V mul_add(V a, V b, V c) { return a * b + c; }
  static V neg_mul_add(V a, V b, V c) { return c - a * b; }
  // As Highway's Min and Max on x86: the second operand where either is NaN.
  static V min(V a, V b) { return a < b ? a : b; }
  static V max(V a, V b) { return a > b ? a : b; }
  static V sqrt(V a) { return std::sqrt(a); }

  static M gt(V a, V b) { return a > b; }
  static V select(M m, V a, V b) { return m ? a : b; }
  static V zero_unless(M m, V a) { return m ? a : 0.0f; }
};

}  // namespace imx
