// NRRD volume files (teem's format): the reader behind read_volume; write_nrrd is public.
#pragma once
#include <filesystem>

#include "intermix/io.hpp"
#include "intermix/volume.hpp"

namespace imx::detail {

// Reads a 3D scalar NRRD volume (.nrrd with attached data, or a .nhdr header with a detached
// data file). Throws imx::Error naming the file and the field or fault.
VolumeData read_nrrd(const std::filesystem::path& file, int frame = 0);

// read_nrrd(file)'s dims, storage type and placement, from the header alone (the data is
// neither opened nor checked). Throws imx::Error naming the file as read_nrrd does.
VolumeHeader read_nrrd_header(const std::filesystem::path& file);

// crop(read_nrrd(file), box), reading only the box's bytes of uncompressed data and keeping
// only the box of compressed data; the header and the data's length are checked as read_nrrd
// checks them. Throws imx::Error naming the file, also for a box that is empty or leaves the
// grid.
VolumeData read_nrrd_region(const std::filesystem::path& file, const VoxelBox& box,
                                int frame = 0);

}  // namespace imx::detail
