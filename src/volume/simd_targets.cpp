#include "volume/simd_targets.hpp"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "volume/simd_targets.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "volume/lanes-inl.hpp"

HWY_BEFORE_NAMESPACE();
namespace imx::HWY_NAMESPACE {

int lane_count() {
  return lanes::kLanes;
}

}  // namespace imx::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <mutex>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "volume/wide_scalar.hpp"

namespace imx {
namespace {

HWY_EXPORT(lane_count);

// The compiled targets, widest first (Highway's bits rise as targets narrow).
std::vector<int64_t> compiled_targets() {
  std::vector<int64_t> out;
  for (int64_t bit = 1; bit != 0 && bit <= HWY_TARGETS; bit <<= 1)
    if (HWY_TARGETS & bit) out.push_back(bit);
  return out;
}

// What the machine runs, read before any limit (Highway's SupportedTargets() reports the limit).
int64_t machine_targets() {
  static const int64_t supported = [] {
    hwy::SetSupportedTargetsForTest(0);
    return hwy::SupportedTargets();
  }();
  return supported;
}

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

// The limit to target `name` (limit_simd_target), IMX_SIMD aside.
void limit_to(std::string_view name) {
  const int64_t supported = machine_targets();
  hwy::SetSupportedTargetsForTest(0);
  if (name.empty()) return;
  std::vector<int64_t> runs;
  std::vector<std::string> names;
  for (int64_t t : compiled_targets())
    if (supported & t) runs.push_back(t), names.emplace_back(hwy::TargetName(t));
  for (size_t i = 0; i < runs.size(); ++i) {
    if (upper(name) == names[i] || (upper(name) == "LOWEST" && i + 1 == runs.size())) {
      hwy::SetSupportedTargetsForTest(runs[i]);
      return;
    }
  }
  throw Error(
      fmt::format("SIMD target '{}' is not one this build runs on this machine: {} (or lowest)",
                  name, fmt::join(names, ", ")));
}

}  // namespace

std::vector<std::string> simd_targets() {
  std::vector<std::string> out;
  for (int64_t t : compiled_targets())
    if (machine_targets() & t) out.emplace_back(hwy::TargetName(t));
  return out;
}

std::string simd_target() {
  apply_simd_environment();
  for (int64_t t : compiled_targets())
    if (hwy::SupportedTargets() & t) return hwy::TargetName(t);
  return hwy::TargetName(HWY_STATIC_TARGET);
}

bool wide_scalar_available() {
  apply_simd_environment();
#if HWY_ARCH_X86
  constexpr int64_t kAvx2OrWider = (int64_t{HWY_AVX2} << 1) - 1;  // bits rise as targets narrow
  return (hwy::SupportedTargets() & kAvx2OrWider) != 0;
#else
  return false;
#endif
}

int simd_lanes() {
  apply_simd_environment();
  return HWY_DYNAMIC_DISPATCH(lane_count)();
}

void limit_simd_target(std::string_view name) {
  // IMX_SIMD first: applied at the next kernel's call, it would replace this limit.
  apply_simd_environment();
  limit_to(name);
}

void apply_simd_environment() {
  static std::once_flag once;
  std::call_once(once, [] {
    const char* name = std::getenv("IMX_SIMD");
    if (!name || !*name) return;
    try {
      limit_to(name);
    } catch (const Error& e) {
      throw Error(fmt::format("IMX_SIMD={}: {}", name, e.what()));
    }
  });
}

}  // namespace imx
#endif  // HWY_ONCE
