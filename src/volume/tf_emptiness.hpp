// TfEmptiness: O(1) answer to "is the TF opacity zero for every value in [lo, hi]?".
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "volume/tf_lut.hpp"

namespace imx {

// A prefix count of the LUT entries with non-zero opacity. TfLut::lookup blends the entries on
// either side of a value's LUT position, so a range is empty when every entry from
// floor(position(lo)) to ceil(position(hi)) is transparent: conservative, never "empty" when
// some value in the range has alpha > 0 (a blend of zeros is exactly zero).
class TfEmptiness {
 public:
  TfEmptiness() = default;
  explicit TfEmptiness(const TfLut& lut);
  size_t bytes() const {
    return prefix_.capacity() * sizeof(uint32_t) +
           (next_.capacity() + prev_.capacity()) * sizeof(int);
  }

  // Pure and O(1). A NaN or inverted range is never empty.
  bool is_empty(float lo, float hi) const {
    if (!(lo <= hi) || prefix_.empty()) return false;
    // Entries floor(x) and ceil(x) carry the weight at LUT position x (an integer x reads one).
    int first = static_cast<int>(std::floor(position(lo)));
    int last = static_cast<int>(std::ceil(position(hi)));
    return prefix_[last + 1] == prefix_[first];
  }

  // is_empty(min(a, b), max(a, b)), the test of a ray piece with end values a and b. With a TF
  // of at most kMaxRuns runs of transparent entries (the usual case) it is a few comparisons
  // with the value intervals that map into those runs, not two LUT positions, a floor, a ceil
  // and two table reads: ray marchers run it on every piece. Same answers, NaNs included.
  // Always inlined, also into the marcher's x86-64-v3 copy (wide_scalar.hpp).
  [[gnu::always_inline]] bool is_empty_between(float a, float b) const {
    if (runs_ > kMaxRuns) return is_empty(std::min(a, b), std::max(a, b));
    if (!(a == a)) return false;
    b = b == b ? b : a;  // as std::min and std::max treat a NaN second argument
    float lo = std::min(a, b), hi = std::max(a, b);
    bool empty = false;
    for (int k = 0; k < kMaxRuns; ++k) empty |= (lo >= run_lo_[k]) & (hi <= run_hi_[k]);
    return empty;
  }

  static constexpr int kMaxRuns = 4;

  // The value intervals [lo[k], hi[k]] behind is_empty_between(), for callers that test many
  // pieces at once (unused slots never match); false when the TF has more than kMaxRuns runs.
  bool value_runs(float (&lo)[kMaxRuns], float (&hi)[kMaxRuns]) const {
    if (runs_ > kMaxRuns) return false;
    std::copy(run_lo_, run_lo_ + kMaxRuns, lo);
    std::copy(run_hi_, run_hi_ + kMaxRuns, hi);
    return true;
  }

  // The part [u0, u1] of the linear ramp s(u) = s_f + u (s_b - s_f), u in [0, 1], outside which
  // the TF opacity is zero: only the two ends are trimmed (empty stretches inside are kept).
  // Pure and O(1); returns {0, 1} when nothing can be trimmed.
  glm::vec2 visible_part(float s_f, float s_b) const {
    if (prefix_.empty() || !(s_f == s_f) || !(s_b == s_b)) return {0.0f, 1.0f};
    // Raw LUT positions keep the ramp linear in u; the table clamps them only where it reads.
    float rf = (s_f - lo_) * inv_step_, rb = (s_b - lo_) * inv_step_;
    float xf = position(s_f), xb = position(s_b);
    if (xf == xb) return {0.0f, 1.0f};
    // Entry j is the first non-empty one a rising ramp meets: the value is non-zero past j - 1;
    // on a falling ramp, entry k is the first one met, non-zero below k + 1.
    auto rising_start = [&](float x) { return static_cast<float>(next_[int(std::ceil(x))] - 1); };
    auto falling_start = [&](float x) { return static_cast<float>(prev_[int(std::floor(x))] + 1); };
    float a = rf, b = rb;  // raw LUT positions where the visible part starts and ends
    if (xf < xb) {
      if (is_zero_at(xf)) a = rising_start(xf);
      if (is_zero_at(xb)) b = falling_start(xb);
    } else {
      if (is_zero_at(xf)) a = falling_start(xf);
      if (is_zero_at(xb)) b = rising_start(xb);
    }
    float inv = 1.0f / (rb - rf);
    float u0 = std::clamp((a - rf) * inv, 0.0f, 1.0f), u1 = std::clamp((b - rf) * inv, 0.0f, 1.0f);
    return u0 <= u1 ? glm::vec2(u0, u1) : glm::vec2(0.0f, 1.0f);
  }

 private:
  // The LUT position TfLut::lookup computes for `value` (the same arithmetic and clamping).
  float position(float value) const {
    float x = (value - lo_) * inv_step_;
    return x > 0.0f ? std::min(x, static_cast<float>(size_ - 1)) : 0.0f;
  }

  // Whether the blended LUT value at position x is exactly zero.
  bool is_zero_at(float x) const {
    int lo = static_cast<int>(std::floor(x)), hi = static_cast<int>(std::ceil(x));
    return prefix_[hi + 1] == prefix_[lo];
  }

  std::vector<uint32_t> prefix_;  // prefix_[i]: entries below i with alpha > 0
  std::vector<int> next_;         // next_[i]: first entry >= i with alpha > 0 (size when none)
  std::vector<int> prev_;         // prev_[i]: last entry <= i with alpha > 0 (-1 when none)
  float lo_ = 0.0f, inv_step_ = 1.0f;
  int size_ = 0;
  // Each maximal run [r0, r1] of transparent entries as the values v with r0 <= position(v) <=
  // r1, the interval [run_lo_, run_hi_] (position() is monotone): a range is empty exactly when
  // it lies in one of them. Unused slots hold no value; runs_ > kMaxRuns: the table answers.
  float run_lo_[kMaxRuns] = {INFINITY, INFINITY, INFINITY, INFINITY};
  float run_hi_[kMaxRuns] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
  int runs_ = 0;
};

}  // namespace imx
