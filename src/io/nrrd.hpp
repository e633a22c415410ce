// NRRD volume files (teem's format): the reader behind read_volume; write_nrrd is public.
#pragma once
#include <filesystem>

#include "intermix/volume.hpp"

namespace imx::detail {

// Reads a 3D scalar NRRD volume (.nrrd with attached data, or a .nhdr header with a detached
// data file). Throws imx::Error naming the file and the field or fault.
VolumeData read_nrrd(const std::filesystem::path& file);

}  // namespace imx::detail
