// 3D Slicer's volume property files (.vp): one volume-rendering preset in nine text lines.
#pragma once
#include <filesystem>

#include "presets/slicer_volume_property.hpp"

namespace imx {

// The most points one function of a .vp file may have.
inline constexpr size_t kMaxVpPoints = 65536;

// Reads `file`: interpolation, shade, ambient, diffuse, specular, specular power, then the
// scalar opacity "N x y ...", gradient opacity "N x y ..." and colour "N x r g b ..." lines.
// Throws imx::Error naming the file, the line and the field for a malformed or non-finite
// number, a count that does not match, unsorted points, a value out of range or too many points.
SlicerVolumeProperty read_vp_file(const std::filesystem::path& file);

}  // namespace imx
