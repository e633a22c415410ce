// Surface thickness: the z-thickness each surface fragment gets as a slab (SPEC §4, §6).
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/camera_model.hpp"
#include "intermix/scene.hpp"
#include "raster/fragment.hpp"
#include "slab/slab.hpp"

namespace imx {

// Relative spacing of float depths: one unit in the last place of t is at most t * 2^-23.
inline constexpr float kFloatDepthQuantum = 1.0f / 8388608.0f;

// Per scene object (Scene::order index): a fixed thickness in mm, or auto (0 for tubes). Auto is
// twice the float depth quantum at the fragment's depth, and at least the world footprint of one
// pixel there, so coplanar surfaces, whose depths differ by rounding only, always overlap.
class SurfaceThickness {
 public:
  SurfaceThickness() = default;
  // `zero` makes every fragment a surface of thickness 0 (the exact multi-fragment methods).
  SurfaceThickness(const Scene& scene, const CameraModel& camera, bool zero = false);

  // Thickness of a fragment of `object` at depth t. Pure.
  float of(uint32_t object, float t) const {
    float fixed = object < by_object_.size() ? by_object_[object] : kAuto;
    if (fixed >= 0.0f) return fixed;
    float footprint = footprint_at_0_ + footprint_per_mm_ * t;
    return std::max(2.0f * kFloatDepthQuantum * t, footprint);
  }

  // The fragment as a virtual slab [t - d, t] (SPEC §4).
  Slab slab(const Fragment& f) const { return Slab{f.t, of(f.object, f.t), f.color}; }

 private:
  static constexpr float kAuto = -1.0f;
  std::vector<float> by_object_;  // mm, or kAuto
  float footprint_at_0_ = 0.0f;   // pixel footprint = footprint_at_0 + footprint_per_mm * t
  float footprint_per_mm_ = 0.0f;
};

}  // namespace imx
