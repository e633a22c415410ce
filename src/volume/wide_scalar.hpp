// run_wide_scalar: the per-ray kernels (the scalar VolumeMarcher and the methods around it)
// compiled twice, at the build's baseline and at x86-64-v3 (AVX2 and FMA), and run at the wider
// one where the machine has it and the SIMD limit (simd_targets.hpp) allows it. A baseline build
// (-march=x86-64-v2) thus keeps the fused multiply-adds that its trilinear fetches, tables and
// shading lose without FMA (7-20% per function).
#pragma once
#include <utility>

namespace imx {

// Whether the scalar kernels may run at x86-64-v3: the machine's allowed SIMD targets include
// AVX2 or wider (so IMX_SIMD=lowest or sse4 runs the baseline copy). A build at x86-64-v3 or
// wider has one copy only. Cheap enough to ask once per frame, not per ray.
bool wide_scalar_available();

#if defined(__x86_64__) && !defined(__AVX2__)
// The wide copy: `body` and what GCC inlines of its callees (flatten), compiled for x86-64-v3's
// vector and bit-manipulation extensions. Calls left out of line (other files, and larger
// functions GCC 12 declines) run their baseline copies, which are correct on any machine.
template <class Body>
[[gnu::flatten, gnu::target("avx2,fma,bmi,bmi2,lzcnt,movbe,f16c,popcnt")]] decltype(auto)
run_wide_copy(Body&& body) {
  return body();
}
#endif

// body() at the wider level when `wide` (wide_scalar_available(), asked once per frame).
template <class Body>
[[gnu::always_inline]] inline decltype(auto) run_wide_scalar(bool wide, Body&& body) {
#if defined(__x86_64__) && !defined(__AVX2__)
  if (wide) return run_wide_copy(std::forward<Body>(body));
#else
  (void)wide;
#endif
  return body();
}

}  // namespace imx
