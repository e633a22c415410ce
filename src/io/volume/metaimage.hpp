// MetaImage volume files (ITK's format): the reader behind read_volume; write_metaimage is public.
#pragma once
#include <filesystem>

#include "intermix/io.hpp"
#include "intermix/volume.hpp"

namespace imx::detail {

// Reads a 2D or 3D scalar MetaImage (.mha with attached data, or a .mhd header with a detached
// raw or zlib-compressed data file). World space is LPS like ITK's, so coordinates are taken
// as they are. Throws imx::Error naming the file and the key or fault.
VolumeData read_metaimage(const std::filesystem::path& file, int frame = 0);

// read_metaimage(file)'s dims, storage type and placement, from the header alone (the data is
// neither opened nor checked). Throws imx::Error naming the file as read_metaimage does.
VolumeHeader read_metaimage_header(const std::filesystem::path& file);

// crop(read_metaimage(file), box), reading only the box's bytes of uncompressed data and keeping
// only the box of compressed data; the header and the data's length are checked as read_metaimage
// checks them. Throws imx::Error naming the file, also for a box that is empty or leaves the
// grid.
VolumeData read_metaimage_region(const std::filesystem::path& file, const VoxelBox& box,
                                 int frame = 0);

}  // namespace imx::detail
