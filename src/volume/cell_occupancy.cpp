#include "volume/cell_occupancy.hpp"

#include <algorithm>
#include <cmath>

namespace imx {

CellOccupancy::CellOccupancy(const BrickMinMax& cell_ranges, const TfEmptiness& tf)
    : grid_(cell_ranges.grid()), bits_((grid_.count() + 63) / 64, 0) {
  std::span<const glm::vec2> r = cell_ranges.ranges();
  for (size_t n = 0; n < r.size(); ++n) {
    // The same slack as the bricks: trilinear blends may round a few ulps outside the range.
    float slack = 1e-5f * std::max(std::abs(r[n].x), std::abs(r[n].y));
    if (!tf.is_empty(r[n].x - slack, r[n].y + slack)) bits_[n >> 6] |= uint64_t{1} << (n & 63);
  }
}

}  // namespace imx
