#include "volume/tf_lut.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx {

glm::vec4 evaluate_transfer_function(const TransferFunction& tf, double value) {
  const auto& p = tf.points;
  if (p.empty()) return glm::vec4(0.0f);
  // A NaN passes both end tests and would make upper_bound return end(): give the first point.
  if (!(value > p.front().value)) return p.front().rgba;
  if (value >= p.back().value) return p.back().rgba;
  auto it = std::upper_bound(p.begin(), p.end(), value,
                             [](double v, const TfPoint& q) { return v < q.value; });
  const TfPoint& b = *it;
  const TfPoint& a = *(it - 1);
  double span = b.value - a.value;
  float f = span > 0.0 ? static_cast<float>((value - a.value) / span) : 1.0f;
  return a.rgba + f * (b.rgba - a.rgba);
}

TfLut::TfLut(const TransferFunction& tf) {
  if (tf.points.empty()) throw Error("transfer_function.points: needs at least one point");
  for (size_t i = 0; i < tf.points.size(); ++i) {
    const TfPoint& q = tf.points[i];
    if (!std::isfinite(q.value))
      throw Error(fmt::format("transfer_function.points[{}]: value is not finite", i));
    for (int c = 0; c < 4; ++c)
      if (!(q.rgba[c] >= 0.0f && q.rgba[c] <= 1.0f))
        throw Error(fmt::format("transfer_function.points[{}]: component {} = {} is not in [0, 1]",
                                i, c + 1, q.rgba[c]));
    if (i > 0 && q.value < tf.points[i - 1].value)
      throw Error(fmt::format("transfer_function.points[{}]: value {} is below the previous {}", i,
                              q.value, tf.points[i - 1].value));
  }
  if (!(tf.unit_distance > 0.0))
    throw Error(
        fmt::format("transfer_function.unit_distance: {} must be positive", tf.unit_distance));
  unit_distance_ = static_cast<float>(tf.unit_distance);
  lo_ = static_cast<float>(tf.points.front().value);
  hi_ = static_cast<float>(tf.points.back().value);
  if (hi_ <= lo_) hi_ = lo_ + 1.0f;
  if (!std::isfinite(hi_ - lo_))
    throw Error(
        fmt::format("transfer_function.points: the values span [{}, {}], wider than a "
                    "float can hold",
                    tf.points.front().value, tf.points.back().value));
  inv_step_ = static_cast<float>(kSize - 1) / (hi_ - lo_);
  table_.resize(kSize);
  for (int i = 0; i < kSize; ++i) {
    double v = lo_ + (hi_ - lo_) * static_cast<double>(i) / (kSize - 1);
    table_[i] = evaluate_transfer_function(tf, v);
    max_opacity_ = std::max(max_opacity_, table_[i].a);
  }
}

}  // namespace imx
