// MRtrix images: .mif (header and data in one file), .mif.gz (the same, gzipped) and .mih (the
// header, its data in another file): the reader behind read_volume for them.
#pragma once
#include <filesystem>
#include <string_view>

#include "intermix/volume.hpp"

namespace imx::detail {

// Reads volume `frame` (index along the 4th axis) of an MRtrix image as MRtrix's documented
// format ("MRtrix image formats") and its reader define it: the image axes are the dim order,
// `layout` saying only how the values are stored (order and direction of each axis on file);
// Int8 to Float64 voxels of either byte order (8-bit signed becomes int16, 32/64-bit values
// float32), `scaling` (offset, scale; anything but 0,1 makes float32); placed by `transform`
// with its columns scaled by `vox` (scanner RAS, made LPS here), or MRtrix's default transform
// when there is none. Throws imx::Error naming the file and the key at fault.
VolumeData read_mrtrix(const std::filesystem::path& file, int frame = 0);

// read_mrtrix's dims, type and placement, with the number of volumes. Reads the header only.
VolumeHeader read_mrtrix_header(const std::filesystem::path& file);

// crop(read_mrtrix(file, frame), box): only the stretch of the data holding the box is read
// from an uncompressed file.
VolumeData read_mrtrix_region(const std::filesystem::path& file, const VoxelBox& box,
                              int frame = 0);

// Whether `first_bytes` (the start of an uncompressed file) begin with MRtrix's "mrtrix image"
// line.
bool is_mrtrix_header(std::string_view first_bytes);

}  // namespace imx::detail
