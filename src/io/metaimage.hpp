// MetaImage volume files (ITK's format): the reader behind read_volume; write_metaimage is public.
#pragma once
#include <filesystem>

#include "intermix/volume.hpp"

namespace imx::detail {

// Reads a 2D or 3D scalar MetaImage (.mha with attached data, or a .mhd header with a detached
// raw or zlib-compressed data file). World space is LPS like ITK's, so coordinates are taken
// as they are. Throws imx::Error naming the file and the key or fault.
VolumeData read_metaimage(const std::filesystem::path& file);

}  // namespace imx::detail
