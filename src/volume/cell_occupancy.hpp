// CellOccupancy: a bit per small cell of voxels saying whether the TF can make it visible.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "volume/brick_grid.hpp"
#include "volume/brick_min_max.hpp"
#include "volume/tf_emptiness.hpp"

namespace imx {

// The fine level under the bricks: inside an occupied brick most ray steps still cross only
// transparent material (air beside skin, say), and asking one bit before sampling is cheaper
// than the two trilinear fetches that would find it out. Cells use BrickGrid's closed regions
// with the apron, so a cell marked empty holds no visible sample. Rebuilt on TF change from
// TF-independent ranges: one O(1) query per cell.
class CellOccupancy {
 public:
  static constexpr int kCellSize = 2;

  CellOccupancy() = default;
  CellOccupancy(const BrickMinMax& cell_ranges, const TfEmptiness& tf);

  // True when every cell the segment from index-space p to q can touch is empty: the box of
  // cells spanned by its ends (a straight segment stays inside that box).
  bool segment_empty(glm::vec3 p, glm::vec3 q) const {
    glm::ivec3 lo = grid_.brick_of(glm::min(p, q)), hi = grid_.brick_of(glm::max(p, q));
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
          size_t n = grid_.index({x, y, z});
          if (bits_[n >> 6] >> (n & 63) & 1) return false;
        }
    return true;
  }

  const BrickGrid& grid() const { return grid_; }

 private:
  BrickGrid grid_;
  std::vector<uint64_t> bits_;  // bit n set: cell n may be visible
};

}  // namespace imx
