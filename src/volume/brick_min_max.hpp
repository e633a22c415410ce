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
  // parallel on up to `threads` threads (0 = all). Depends only on the voxels, not on the TF.
  explicit BrickMinMax(const AnyGrid& voxels, int brick_size = BrickGrid::kDefaultSize,
                       int threads = 0);

  const BrickGrid& grid() const { return grid_; }
  // (min, max) of brick b; a brick holding a NaN reports (-inf, +inf) so it is never skipped.
  glm::vec2 range(glm::ivec3 b) const { return ranges_[grid_.index(b)]; }
  std::span<const glm::vec2> ranges() const { return ranges_; }

 private:
  BrickGrid grid_;
  std::vector<glm::vec2> ranges_;
};

}  // namespace imx
