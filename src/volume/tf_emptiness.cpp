#include "volume/tf_emptiness.hpp"

#include <bit>
#include <cstdint>

namespace imx {

TfEmptiness::TfEmptiness(const TfLut& lut)
    : lo_(lut.lo()), inv_step_(lut.inv_step()), size_(static_cast<int>(lut.entries().size())) {
  const std::vector<glm::vec4>& e = lut.entries();
  prefix_.resize(e.size() + 1);
  prefix_[0] = 0;
  for (size_t i = 0; i < e.size(); ++i) prefix_[i + 1] = prefix_[i] + (e[i].a > 0.0f ? 1 : 0);
  const int n = size_;
  next_.assign(e.size(), n);
  prev_.assign(e.size(), -1);
  for (int i = n - 1, nearest = n; i >= 0; --i) next_[i] = nearest = e[i].a > 0.0f ? i : nearest;
  for (int i = 0, nearest = -1; i < n; ++i) prev_[i] = nearest = e[i].a > 0.0f ? i : nearest;

  // The value intervals of the transparent runs, found by bisection over the floats in order
  // (position() is monotone only for a positive scale: otherwise the table answers).
  if (!(inv_step_ > 0.0f) || !std::isfinite(lo_)) {
    runs_ = kMaxRuns + 1;
    return;
  }
  // Floats in increasing order as unsigned keys (-inf .. +inf; NaNs lie outside).
  auto key = [](float f) {
    uint32_t u = std::bit_cast<uint32_t>(f);
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
  };
  auto from_key = [](uint32_t k) {
    return std::bit_cast<float>((k & 0x80000000u) ? (k & 0x7fffffffu) : ~k);
  };
  // The key of the least float where `pred` holds: false, then true along the floats in order,
  // and true at +inf.
  auto least = [&](auto pred) {
    uint32_t lo = key(-INFINITY), hi = key(INFINITY);
    while (lo < hi) {
      uint32_t mid = lo + (hi - lo) / 2;
      if (pred(from_key(mid)))
        hi = mid;
      else
        lo = mid + 1;
    }
    return lo;
  };
  for (int r0 = 0; r0 < n;) {
    if (e[r0].a > 0.0f) {
      ++r0;
      continue;
    }
    int r1 = r0;
    while (r1 + 1 < n && !(e[r1 + 1].a > 0.0f)) ++r1;
    if (runs_ < kMaxRuns) {
      const float first = static_cast<float>(r0), last = static_cast<float>(r1);
      // Every value reaches position 0, and none passes size - 1.
      run_lo_[runs_] =
          r0 == 0 ? -INFINITY : from_key(least([&](float v) { return position(v) >= first; }));
      run_hi_[runs_] =
          r1 == n - 1 ? INFINITY : from_key(least([&](float v) { return position(v) > last; }) - 1);
    }
    ++runs_;
    r0 = r1 + 1;
  }
}

}  // namespace imx
