// The sample walk of the projection styles and iso-surfaces (SPEC §2) with skipping by brick value
// ranges: a brick whose [min, max] cannot change the running result is jumped in one step.
// Pure: no allocation, no exceptions.
#pragma once
#include <cmath>

#include <glm/glm.hpp>

#include "core/ray.hpp"
#include "volume/brick_min_max.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/volume_marcher.hpp"

namespace imx {

// The bricks one ray crosses, in index space: the value range of the brick holding the ray's
// point at t, and where the ray leaves that brick.
class RangeBricks {
 public:
  RangeBricks() = default;
  RangeBricks(const BrickMinMax* ranges, const PreparedVolume& v, const Ray& ray)
      : ranges_(ranges),
        origin_(v.to_index(ray.origin)),
        dir_(glm::mat3(v.world_to_index) * ray.dir) {}

  bool active() const { return ranges_ != nullptr; }

  glm::vec2 range_at(float t, float& exit) const {
    const BrickGrid& g = ranges_->grid();
    const glm::ivec3 b = g.brick_of(origin_ + t * dir_);
    exit = INFINITY;
    for (int a = 0; a < 3; ++a) {
      if (std::abs(dir_[a]) < 1e-12f) continue;  // parallel: never leaves through this axis
      const float face =
          dir_[a] > 0.0f ? static_cast<float>(std::min((b[a] + 1) * g.size[a], g.voxel_dims[a] - 1))
                         : static_cast<float>(b[a] * g.size[a]);
      exit = std::min(exit, (face - origin_[a]) / dir_[a]);
    }
    return ranges_->range(b);
  }

 private:
  const BrickMinMax* ranges_ = nullptr;
  glm::vec3 origin_{0.0f}, dir_{0.0f};
};

// Visits the points a projection samples on [t0, t1]: t0, every k * step inside (the grid
// anchored at t = 0 that every volume shares) and t1. After each point, skip(range) may say that
// the brick holding it cannot change the result: the walk moves to the last grid point in that
// brick at once, reports it to jumped(t), and goes on from there. visit(t, value) returns false
// to stop; so does the walk.
template <class Visit, class Skip, class Jumped>
bool walk_samples(const PreparedVolume& v, const Ray& ray, double t0, double t1, double step,
                  const RangeBricks& bricks, Visit&& visit, Skip&& skip, Jumped&& jumped) {
  auto value_at = [&](double t) {
    return v.grid.sample(v.to_index(ray.at(static_cast<float>(t))));
  };
  double t = t0;
  if (!visit(t, value_at(t))) return false;
  double cell = grid_cell(t0, step);  // the next point is (cell + 1) * step
  while (t < t1) {
    if (bricks.active()) {
      float exit = 0.0f;
      if (skip(bricks.range_at(static_cast<float>(t), exit))) {
        const double last = std::floor(exit / step) * step;
        if (last >= t1) return true;  // the rest of the span lies in this brick
        if (last > t) {
          t = last;
          cell = grid_cell(t, step);
          jumped(t);
        }
      }
    }
    const double b = std::min(t1, (cell + 1.0) * step);
    cell += 1.0;
    if (!visit(b, value_at(b))) return false;
    t = b;
  }
  return true;
}

// The brick ranges a volume's projection or iso-surface may skip by: null when the frame built
// no skipping structures (the reference) or for X-ray's average, which reads every value.
inline const BrickMinMax* skip_ranges(const PreparedVolume& v) {
  if (v.object->style == VolumeStyle::xray &&
      (v.object->xray_mode == XrayMode::average || !v.accel.emptiness))
    return nullptr;
  return v.accel.ranges.get();
}

}  // namespace imx
