// FreeSurfer MGH volumes (.mgh; gzipped: .mgz, .mgh.gz): the reader behind read_volume.
#pragma once
#include <filesystem>

#include "intermix/volume.hpp"

namespace imx::detail {

// Reads frame `frame` of an MGH file (uchar, int, float or short voxels, big-endian), placed as
// nibabel's MGHHeader.get_affine places it (then RAS becomes LPS); int voxels become float32.
// Only the frame's voxels are held. Throws imx::Error naming the file, also for a frame out of
// range.
VolumeData read_mgh(const std::filesystem::path& file, int frame = 0);

// read_mgh(file)'s dims, storage type and placement, with its frame count and, for several
// frames and a TR in the footer that follows the data, each frame's time (k * TR). Only the
// header is read, except for that footer (an .mgz with several frames is inflated to reach it).
VolumeHeader read_mgh_header(const std::filesystem::path& file);

// crop(read_mgh(file, frame), box), reading only the box's bytes of uncompressed data and
// keeping only the box of compressed data, checked as read_mgh checks the file.
VolumeData read_mgh_region(const std::filesystem::path& file, const VoxelBox& box, int frame = 0);

}  // namespace imx::detail
