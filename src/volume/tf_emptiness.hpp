// TfEmptiness: O(1) answer to "is the TF opacity zero for every value in [lo, hi]?".
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

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

  // Pure and O(1). A NaN or inverted range is never empty.
  bool is_empty(float lo, float hi) const {
    if (!(lo <= hi) || prefix_.empty()) return false;
    // Entries floor(x) and ceil(x) carry the weight at LUT position x (an integer x reads one).
    int first = static_cast<int>(std::floor(position(lo)));
    int last = static_cast<int>(std::ceil(position(hi)));
    return prefix_[last + 1] == prefix_[first];
  }

 private:
  // The LUT position TfLut::lookup computes for `value` (the same arithmetic and clamping).
  float position(float value) const {
    float x = (value - lo_) * inv_step_;
    return x > 0.0f ? std::min(x, static_cast<float>(size_ - 1)) : 0.0f;
  }

  std::vector<uint32_t> prefix_;  // prefix_[i]: entries below i with alpha > 0
  float lo_ = 0.0f, inv_step_ = 1.0f;
  int size_ = 0;
};

}  // namespace imx
