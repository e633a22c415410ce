// BrickMinMax: the smallest and largest scalar each brick's trilinear samples can take.
#pragma once
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "volume/any_grid.hpp"
#include "volume/brick_grid.hpp"

namespace imx {

class BrickMinMax {
 public:
  BrickMinMax() = default;
  // Scans every brick's voxels including its apron (BrickGrid::first_voxel..last_voxel), in
  // parallel on up to `threads` threads (0 = all), for bricks of `shape` cells (BrickGrid::size).
  // Depends only on the voxels, not on the TF.
  explicit BrickMinMax(const AnyGrid& voxels,
                       glm::ivec3 shape = glm::ivec3(BrickGrid::kDefaultSize), int threads = 0);

  const BrickGrid& grid() const { return grid_; }
  // (min, max) of brick b's finite voxels: NaN and inf voxels are no data, left out (samples
  // that read them are no data too). A brick of no data only is (+inf, -inf): see holds_data.
  glm::vec2 range(glm::ivec3 b) const { return ranges_[grid_.index(b)]; }
  // Whether a range has any value: false for a brick of no data, which every walk may skip.
  static bool holds_data(glm::vec2 range) { return range.x <= range.y; }
  std::span<const glm::vec2> ranges() const { return ranges_; }
  size_t bytes() const { return ranges_.capacity() * sizeof(glm::vec2); }

 private:
  BrickGrid grid_;
  std::vector<glm::vec2> ranges_;
};

}  // namespace imx
