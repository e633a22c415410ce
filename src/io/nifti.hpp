// NIfTI-1 volume files (.nii, .nii.gz) through nifticlib: the reader behind read_volume.
#pragma once
#include <filesystem>

#include "intermix/io.hpp"
#include "intermix/volume.hpp"

namespace imx::detail {

// Reads the first 3D volume of a NIfTI-1 file (a 4D series gives its first time point),
// converting RAS to LPS and applying scl_slope/scl_inter. Throws imx::Error naming the file.
VolumeData read_nifti(const std::filesystem::path& file, int frame = 0);

// read_nifti(file)'s dims, storage type and placement, from the header alone (the data is
// neither opened nor checked). Throws imx::Error naming the file as read_nifti does.
VolumeHeader read_nifti_header(const std::filesystem::path& file);

// crop(read_nifti(file), box), reading only the box's bytes of uncompressed data and keeping
// only the box of compressed data; the header and the data's length are checked as read_nifti
// checks them. Throws imx::Error naming the file, also for a box that is empty or leaves the
// grid.
VolumeData read_nifti_region(const std::filesystem::path& file, const VoxelBox& box,
                                int frame = 0);

}  // namespace imx::detail
