#include "volume/brick_occupancy.hpp"

#include <algorithm>
#include <cmath>

namespace imx {

BrickOccupancy::BrickOccupancy(const BrickMinMax& ranges, const TfEmptiness& tf)
    : BrickOccupancy(ranges, [&tf](float lo, float hi) { return tf.is_empty(lo, hi); }) {}

BrickOccupancy::BrickOccupancy(const BrickMinMax& ranges,
                               const std::function<bool(float, float)>& is_empty)
    : grid_(ranges.grid()), distance_(kOctants * grid_.count() + kSpareBytes) {
  std::vector<uint8_t> occupied(grid_.count());
  std::span<const glm::vec2> r = ranges.ranges();
  for (size_t n = 0; n < r.size(); ++n) {
    // Trilinear blends round by a few ulps, so a sample may sit just outside the voxel range.
    float slack = 1e-5f * std::max(std::abs(r[n].x), std::abs(r[n].y));
    const bool empty = !BrickMinMax::holds_data(r[n]) || is_empty(r[n].x - slack, r[n].y + slack);
    occupied[n] = empty ? 0 : 1;
    occupied_count_ += occupied[n];
  }
  octant_distance(occupied, grid_.dims, std::span(distance_).first(kOctants * grid_.count()));
}

}  // namespace imx
