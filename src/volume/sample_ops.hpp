// ScalarOps: the per-sample arithmetic vocabulary on one float. sample_formulas.hpp writes each
// per-sample formula once against this vocabulary; the lane kernels instantiate the same
// formulas with LaneOps (lanes-inl.hpp: the same names on Highway vectors, one ray per lane).
// Pure: no allocation, no exceptions, no globals.
#pragma once
#include <cmath>
#include <cstddef>

#include <glm/glm.hpp>

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
  static M lt(V a, V b) { return a < b; }
  static M both(M a, M b) { return a && b; }
  static M either(M a, M b) { return a || b; }
  static M not_(M a) { return !a; }
  static bool none(M a) { return !a; }
  static V select(M m, V a, V b) { return m ? a : b; }
  static V zero_unless(M m, V a) { return m ? a : 0.0f; }

  // Voxel indices (64-bit: a grid may hold more than 2^31 voxels) and their masks.
  using I = std::ptrdiff_t;
  using MI = bool;
  static I isplat(int x) { return x; }
  static I iadd(I a, I b) { return a + b; }
  static I ineg(I a) { return -a; }
  static MI igt(I a, I b) { return a > b; }
  static MI ilt(I a, I b) { return a < b; }
  static MI ieq(I a, I b) { return a == b; }
  static I iselect(MI m, I a, I b) { return m ? a : b; }
  static I izero_unless(MI m, I a) { return m ? a : 0; }
  static M float_mask(MI m) { return m; }

  // Three-vectors (directions, normals, RGB): glm's, which the compiler keeps in one register.
  using V3 = glm::vec3;
  static V3 splat3(const glm::vec3& v) { return v; }
  static V dot(const V3& a, const V3& b) { return glm::dot(a, b); }
  static V3 scale(V k, const V3& a) { return k * a; }
  static V3 add(const V3& a, const V3& b) { return a + b; }
  static V3 mul(const V3& a, const V3& b) { return a * b; }
  static V3 mul_add(const V3& a, const V3& b, const V3& c) { return a * b + c; }
  static V3 zero_unless(M m, const V3& a) { return m ? a : V3(0.0f); }
  static V3 negate_if(M m, const V3& a) { return m ? -a : a; }
};

}  // namespace imx
