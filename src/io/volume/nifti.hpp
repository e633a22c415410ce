// NIfTI-1 and NIfTI-2 volume files (.nii, .nii.gz, and .hdr/.img pairs) and Analyze 7.5 pairs:
// the reader behind read_volume.
#pragma once
#include <filesystem>

#include "intermix/io.hpp"
#include "intermix/volume.hpp"

namespace imx::detail {

// Reads frame `frame` of a NIfTI-1 or NIfTI-2 single file (.nii, .nii.gz; magic "n+1"/"n+2"),
// or of a pair named by its .hdr or its .img (either may be gzipped: .hdr.gz, .img.gz), which
// is NIfTI-1 ("ni1"), NIfTI-2 ("ni2") or Analyze 7.5 (no magic). RAS becomes LPS and the
// intensity scaling is applied (the voxels are then float32). A 4-D file is a time series
// (dim[4] frames) or a set of components (dim[5]); frame 0 of a 3-D file is the file. Only
// the frame's voxels are held. Throws imx::Error naming the file, also for a frame out of range
// and for a .nii whose magic is not NIfTI's (never read as Analyze).
VolumeData read_nifti(const std::filesystem::path& file, int frame = 0);

// read_nifti(file)'s dims, storage type and placement, with its frame count and, for a time
// series whose header gives the frame time (pixdim[4] in xyzt_units' seconds, ms or us), each
// frame's time, from the header alone (the data is neither opened nor checked). Throws
// imx::Error naming the file as read_nifti does.
VolumeHeader read_nifti_header(const std::filesystem::path& file);

// crop(read_nifti(file, frame), box), reading only the box's bytes of uncompressed data and
// keeping only the box of compressed data; the header and the data's length (every frame's)
// are checked as read_nifti checks them. Throws imx::Error naming the file, also for a box that
// is empty or leaves the grid.
VolumeData read_nifti_region(const std::filesystem::path& file, const VoxelBox& box, int frame = 0);

}  // namespace imx::detail
