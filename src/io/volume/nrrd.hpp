// NRRD volume files (teem's format): the reader behind read_volume; write_nrrd is public.
#pragma once
#include <filesystem>

#include "intermix/io.hpp"
#include "intermix/volume.hpp"

namespace imx::detail {

// Reads frame `frame` of a NRRD file (.nrrd with attached data, or a .nhdr header with one or
// several detached data files; raw, gzip, bzip2, ascii or hex data). A 3-D file holds one frame;
// a 4-D file holds as many as its one non-spatial axis (the 'none' entry of 'space directions',
// else the axis 'kinds' calls time, list, vector, ...) has entries, interleaved when that axis
// is the fastest. Throws imx::Error naming the file and the field or fault, also for a frame out
// of range.
VolumeData read_nrrd(const std::filesystem::path& file, int frame = 0);

// read_nrrd(file)'s dims, storage type, placement, frame count and frame labels (b-values and
// gradients of DWMRI files), from the header alone (the data is neither opened nor checked).
// Throws imx::Error naming the file as read_nrrd does.
VolumeHeader read_nrrd_header(const std::filesystem::path& file);

// crop(read_nrrd(file, frame), box), reading only the box's bytes of uncompressed data and
// keeping only the box of compressed or text data; the header and the data's length are checked
// as read_nrrd checks them. Throws imx::Error naming the file, also for a box that is empty or
// leaves the grid.
VolumeData read_nrrd_region(const std::filesystem::path& file, const VoxelBox& box, int frame = 0);

}  // namespace imx::detail
