// BrickOccupancy: which bricks the current TF makes visible, and how far each empty one is from
// one in each direction.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "volume/brick_grid.hpp"
#include "volume/brick_min_max.hpp"
#include "volume/octant_distance.hpp"
#include "volume/tf_emptiness.hpp"

namespace imx {

// Rebuilt on every TF change from the TF-independent BrickMinMax: O(bricks), no voxel access.
class BrickOccupancy {
 public:
  BrickOccupancy(const BrickMinMax& ranges, const TfEmptiness& tf);
  // The same with any test of a brick's value range [lo, hi] (a label volume's visible labels).
  BrickOccupancy(const BrickMinMax& ranges, const std::function<bool(float, float)>& is_empty);

  const BrickGrid& grid() const { return grid_; }
  bool occupied(glm::ivec3 b) const { return distance_[kOctants * grid_.index(b)] == 0; }
  // 0 for an occupied brick, else the Chebyshev distance in bricks to the nearest occupied one in
  // `octant` (octant_distance(): all a ray moving that way may jump over).
  uint8_t distance(glm::ivec3 b, int octant) const {
    return distance_[kOctants * grid_.index(b) + octant];
  }
  // octant_distance() of the occupied bricks (kOctants bytes per brick), followed by kSpareBytes
  // readable bytes, so that a 32-bit load at any entry stays inside (lane gathers).
  const uint8_t* padded_distances() const { return distance_.data(); }
  static constexpr size_t kSpareBytes = 3;
  size_t occupied_count() const { return occupied_count_; }
  size_t bytes() const { return distance_.capacity(); }

 private:
  BrickGrid grid_;
  std::vector<uint8_t> distance_;
  size_t occupied_count_ = 0;
};

}  // namespace imx
