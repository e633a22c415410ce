// TfLut: a transfer function baked into a lookup table, and opacity correction for a step.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "intermix/scene.hpp"

namespace imx {

class TfLut {
 public:
  static constexpr int kSize = 4096;

  TfLut() = default;
  // Throws imx::Error when the points are empty, unsorted or out of [0, 1].
  explicit TfLut(const TransferFunction& tf);

  // Straight RGB and the opacity of unit_distance() mm, linearly interpolated between entries.
  glm::vec4 lookup(float value) const {
    float x = (value - lo_) * inv_step_;
    x = x > 0.0f ? std::min(x, static_cast<float>(kSize - 1)) : 0.0f;  // NaN goes to 0
    int i = std::min(static_cast<int>(x), kSize - 2);
    float f = x - static_cast<float>(i);
    return table_[i] + f * (table_[i + 1] - table_[i]);
  }

  // The baked entries and the value-to-entry scale lookup() uses: for tables derived from the LUT.
  const std::vector<glm::vec4>& entries() const { return table_; }
  float inv_step() const { return inv_step_; }

  float unit_distance() const { return unit_distance_; }
  float lo() const { return lo_; }
  float hi() const { return hi_; }
  // Largest opacity anywhere in the table (0 means the volume is invisible).
  float max_opacity() const { return max_opacity_; }

 private:
  std::vector<glm::vec4> table_;
  float lo_ = 0.0f, hi_ = 1.0f, inv_step_ = 1.0f;
  float unit_distance_ = 1.0f;
  float max_opacity_ = 0.0f;
};

// Evaluates a piecewise-linear transfer function exactly (no table): for tests and tools.
glm::vec4 evaluate_transfer_function(const TransferFunction& tf, double value);

// Opacity of a step of dt mm for material whose opacity over dt0 mm is `alpha` (SPEC §2).
inline float correct_opacity(float alpha, float dt, float dt0) {
  if (alpha <= 0.0f) return 0.0f;
  if (alpha >= 1.0f) return 1.0f;
  return 1.0f - std::pow(1.0f - alpha, dt / dt0);
}

}  // namespace imx
