// SpecularTable: x^n for the specular term of one material, as a lookup instead of a chain of
// multiplies (the chain was 12% of a shaded volume frame). Pure lookups; built once per frame.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>

namespace imx {

class SpecularTable {
 public:
  static constexpr int kEntries = 1024;

  SpecularTable() : SpecularTable(1.0f) {}
  // Tabulates x^n over [x_min, 1], where x_min^n = kCutoff: the entries are evenly spaced in
  // n·ln(x), so linear interpolation has the same small relative error (~3e-5) for every n.
  // Exponents below 1 are steep at 0 and are computed exactly instead.
  explicit SpecularTable(float n) : n_(n) {
    exact_ = !(n >= 1.0f) || !std::isfinite(n);
    if (exact_) return;
    x_min_ = static_cast<float>(std::exp(std::log(double{kCutoff}) / n));
    inv_step_ = static_cast<float>((kEntries - 1) / (1.0 - x_min_));
    // In double: for large n, x^n amplifies the rounding of x a thousandfold.
    for (int i = 0; i < kEntries; ++i) {
      double x = x_min_ + (1.0 - x_min_) * i / (kEntries - 1);
      values_[i] = static_cast<float>(std::pow(x, double{n}));
    }
    values_[kEntries] = 1.0f;  // so that x = 1 may read one entry ahead
  }

  // The table itself, for vectorized lookups that follow operator() (not for exact tables).
  struct View {
    const float* values;  // kEntries + 1
    float x_min, inv_step;
  };
  bool exact() const { return exact_; }
  View view() const { return {values_.data(), x_min_, inv_step_}; }

  // x^n for x in [0, 1]; values below kCutoff are 0 (they cannot show).
  float operator()(float x) const {
    if (exact_) return std::pow(std::max(x, 0.0f), n_);
    float u = (x - x_min_) * inv_step_;
    if (!(u > 0.0f)) return 0.0f;
    u = std::min(u, static_cast<float>(kEntries - 1));
    int i = static_cast<int>(u);
    float f = u - static_cast<float>(i);
    return values_[i] + f * (values_[i + 1] - values_[i]);
  }

 private:
  static constexpr float kCutoff = 1e-7f;
  std::array<float, kEntries + 1> values_{};
  float n_ = 1.0f;
  float x_min_ = 0.0f;
  float inv_step_ = 1.0f;
  bool exact_ = true;
};

}  // namespace imx
