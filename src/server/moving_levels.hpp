// The viewer's moving frames at a level of detail: while the user drags, a large volume whose
// voxels are smaller than the frame's pixels is drawn from a coarser copy of itself (each level
// half the last along every axis, built in memory on first use: at most a seventh of the voxels
// more), so a drag marches only the voxels its pixels can show. Still frames keep full
// resolution (docs/big_data.md, "Levels of detail").
#pragma once
#include <cstddef>
#include <memory>
#include <vector>

#include "intermix/scene.hpp"

namespace imx::server {

// Volumes with fewer voxels than this are drawn whole: they already move at the frame budget.
inline constexpr size_t kMovingLevelVoxels = size_t{1} << 24;

class MovingLevels {
 public:
  // Replaces in `scene` (a moving frame's, at the frame's image size) each large scalar volume
  // held whole by its coarsest level whose voxel's longest edge fits a pixel at the volume's
  // nearest point; returns the coarsest level used (0: none).
  int apply(Scene& scene);

 private:
  struct Levels {
    std::weak_ptr<const VolumeData> base;
    std::vector<std::shared_ptr<const VolumeData>> coarser;  // level 1, 2, ...
  };
  // Level `level` (>= 1) of `base`, built with the levels before it when missing.
  std::shared_ptr<const VolumeData> level_of(const std::shared_ptr<const VolumeData>& base,
                                             int level);

  std::vector<Levels> cache_;
};

}  // namespace imx::server
