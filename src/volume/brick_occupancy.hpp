// BrickOccupancy: which bricks the current TF makes visible, and how far each empty one is from
// one.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "volume/brick_grid.hpp"
#include "volume/brick_min_max.hpp"
#include "volume/tf_emptiness.hpp"

namespace imx {

// Rebuilt on every TF change from the TF-independent BrickMinMax: O(bricks), no voxel access.
class BrickOccupancy {
 public:
  BrickOccupancy(const BrickMinMax& ranges, const TfEmptiness& tf);

  const BrickGrid& grid() const { return grid_; }
  bool occupied(glm::ivec3 b) const { return distance_[grid_.index(b)] == 0; }
  // 0 for an occupied brick, else the Chebyshev distance in bricks to the nearest occupied one
  // (saturated at 255, which is also the value when no brick is occupied).
  uint8_t distance(glm::ivec3 b) const { return distance_[grid_.index(b)]; }
  std::span<const uint8_t> distances() const { return std::span(distance_).first(grid_.count()); }
  // distances() followed by kSpareBytes readable bytes, so that a 32-bit load at any brick
  // stays inside (lane gathers).
  const uint8_t* padded_distances() const { return distance_.data(); }
  static constexpr size_t kSpareBytes = 3;
  size_t occupied_count() const { return occupied_count_; }

 private:
  BrickGrid grid_;
  std::vector<uint8_t> distance_;
  size_t occupied_count_ = 0;
};

}  // namespace imx
