// NIfTI-1 volume files (.nii, .nii.gz) through nifticlib: the reader behind read_volume.
#pragma once
#include <filesystem>

#include "intermix/volume.hpp"

namespace imx::detail {

// Reads the first 3D volume of a NIfTI-1 file (a 4D series gives its first time point),
// converting RAS to LPS and applying scl_slope/scl_inter. Throws imx::Error naming the file.
VolumeData read_nifti(const std::filesystem::path& file);

}  // namespace imx::detail
