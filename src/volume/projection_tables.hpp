// What the projection styles (SPEC §2) read of a transfer function besides its LUT: the value
// bounds that let MIP / MinIP skip bricks and stop, and X-ray's attenuation per value.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "volume/tf_lut.hpp"

namespace imx {

// Bounds read off the baked LUT (what lookup() returns), each a little conservative so float
// rounding never moves a visible value across one.
struct ProjectionLimits {
  float invisible_up_to =
      -INFINITY;  // opacity 0 for every value <= this: MIP's maximum starts here
  float invisible_from =
      INFINITY;                    // opacity 0 for every value >= this: MinIP's minimum starts here
  float constant_from = INFINITY;  // the same RGBA for every value >= this: MIP stops there
  float constant_up_to = -INFINITY;  // the same RGBA for every value <= this: MinIP stops there
  // Whether the values of opacity 0 lie only below (above) every visible one, so that a brick the
  // TF leaves empty cannot hold a maximum (minimum) that shows: MIP (MinIP) may skip it.
  bool invisible_only_below = false;
  bool invisible_only_above = false;
};

ProjectionLimits projection_limits(const TfLut& lut);

// X-ray's line integral reads the attenuation mu = -ln(1 - alpha) / unit_distance per mm that the
// TF's opacity stands for, so a radiograph of a slab has the opacity DVR gives it without its
// emission. Entries hold (mu r, mu g, mu b, mu), interpolated like TfLut::lookup.
class AttenuationTable {
 public:
  AttenuationTable() = default;
  explicit AttenuationTable(const TfLut& lut);

  glm::vec4 lookup(float value) const {
    float x = (value - lo_) * inv_step_;
    x = x > 0.0f ? std::min(x, static_cast<float>(TfLut::kSize - 1)) : 0.0f;  // NaN goes to 0
    int i = std::min(static_cast<int>(x), TfLut::kSize - 2);
    float f = x - static_cast<float>(i);
    return table_[i] + f * (table_[i + 1] - table_[i]);
  }
  const glm::vec4* data() const { return table_.data(); }
  float lo() const { return lo_; }
  float inv_step() const { return inv_step_; }

 private:
  std::vector<glm::vec4> table_;
  float lo_ = 0.0f, inv_step_ = 1.0f;
};

}  // namespace imx
