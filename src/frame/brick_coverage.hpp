// BrickCoverage: which blocks of 4 x 2 pixels a volume's occupied bricks can show in, so that
// no method marches a ray that would find nothing (FrameSetup builds one per volume).
#pragma once
#include <cstdint>
#include <vector>

#include "core/camera_model.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

class BrickCoverage {
 public:
  static constexpr int kBlockWidth = 4, kBlockHeight = 2;

  // Conservative: a block is covered when a pixel centre in it may lie within the screen
  // rectangle (a pixel wider each side, for rounding) of the corners of an occupied brick's region
  // (BrickGrid::first_voxel..last_voxel), or of the whole grid when `v` has no occupancy. Grids of
  // more than 32 bricks a side are taken in cells of several bricks, occupied when any of them
  // is, so that the work per frame stays below 33^3 corners. Every block is covered when a corner
  // lies behind the eye (or the eye inside the grid).
  BrickCoverage(const PreparedVolume& v, const CameraModel& camera);

  // Whether the block holding pixel (x, y) is covered.
  bool covered(int x, int y) const {
    return blocks_[static_cast<size_t>(y / kBlockHeight) * columns_ + x / kBlockWidth] != 0;
  }

 private:
  // Marks the blocks whose pixel centres may lie in [lo, hi] (image positions).
  void mark(glm::dvec2 lo, glm::dvec2 hi);

  int width_, height_, columns_;
  std::vector<uint8_t> blocks_;
};

}  // namespace imx
