// The SIMD targets the lane kernels run on (Google Highway's dispatch at run time), and a limit
// on them for tests, benchmarks and machines whose widest target is unwanted.
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace imx {

// The targets this build compiled the lane kernels for that this machine runs, widest first, by
// Highway's names ("AVX3", "AVX2", "SSE4", "EMU128", "NEON", ...).
std::vector<std::string> simd_targets();

// The target the lane kernels run on now, and its float lanes per vector (1 to 16).
std::string simd_target();
int simd_lanes();

// Makes the lane kernels run on target `name` (case-insensitive, one of simd_targets(), or
// "lowest" for the last of them); an empty name lifts the limit. Throws imx::Error naming the
// value otherwise. IMX_SIMD is applied first (apply_simd_environment), so that it never replaces
// this limit later.
void limit_simd_target(std::string_view name);

// Applies the environment's IMX_SIMD (a target's name) once per process, before the first
// kernel runs; an unknown name throws imx::Error naming it, at every kernel call.
void apply_simd_environment();

}  // namespace imx
