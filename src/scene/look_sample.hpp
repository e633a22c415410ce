// The voxels an automatic look is chosen from when a volume is read by region (a brick of it,
// or none of it while a render in bricks plans its parts): whole slices spread evenly through
// the volume, so that every brick and the plan choose the same look from the same values.
#pragma once
#include <functional>

#include "intermix/volume.hpp"

namespace imx {

// Up to 16 whole k-slices evenly spaced through the grid `header` describes (fewer, or a band
// of rows, when a slice is large), read with `load_box` and stacked as one grid in their order.
VolumeData look_sample(const VolumeHeader& header,
                       const std::function<VolumeData(const VoxelBox&)>& load_box);

}  // namespace imx
