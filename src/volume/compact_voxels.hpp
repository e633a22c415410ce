// Float voxels held in a 16-bit integer type when every value is one: CT converted to float32
// (a tilt-corrected or resampled series) keeps whole Hounsfield units, and half the bytes per
// sample makes its march as fast as the same voxels stored as int16.
#pragma once
#include <optional>

#include "intermix/volume.hpp"

namespace imx {

// The voxels of a float32 volume as int16 (or, for values above int16's range, uint16) when every
// one is a whole number that type holds exactly: nullopt when a voxel is NaN, infinite,
// fractional or outside both ranges, and for a volume of another type or with colours. -0.0
// becomes 0, the only value that changes (it compares equal).
std::optional<VoxelStorage> compact_integer_voxels(const VolumeData& data);

}  // namespace imx
