// Displacement fields as ITK and ANTs write them (a NIfTI vector image: intent 1007, dims
// x, y, z, 1, 3, vectors in LPS mm): the map of the field's (fixed) space to the moving space,
// x -> x + d(x), applied by resampling the moving volume once.
#pragma once
#include <filesystem>

#include "intermix/volume.hpp"

namespace imx {

// True when `file` is a NIfTI (.nii, .nii.gz) whose header gives intent code 1007
// (NIFTI_INTENT_VECTOR): read_transform_file's linear formats are anything else.
bool is_displacement_field(const std::filesystem::path& file);

// `moving` resampled on its own grid (its dims and index_to_world, now read as points of the
// fixed space): the voxel at world x takes moving's trilinear value at x + d(x), d the field's
// vector sampled trilinearly at x (zero outside the field's box, as ITK's
// DisplacementFieldTransform gives). Float32; NaN (no data) where x + d(x) leaves `moving`.
// Throws imx::Error naming `field` unless it is 5-D x, y, z, 1, 3 with intent 1007.
// `seconds`, when given, gets the time the resampling took (without reading the field).
VolumeData warp_volume(const VolumeData& moving, const std::filesystem::path& field,
                       double* seconds = nullptr);

}  // namespace imx
