// TIFF volumes through libtiff: a multi-page TIFF or BigTIFF (one page per slice; ImageJ
// hyperstacks and OME-TIFF with their channels and time points) or a folder of single-page
// TIFFs (docs/big_data.md, "TIFF stacks and OME-TIFF"): the volume table's TIFF row.
#pragma once
#include <filesystem>

#include "intermix/volume.hpp"

namespace imx::detail {

// Time point `frame` of channel `channel` of `path` (a file, or a folder of TIFF slices): pages
// become k, rows j, columns i. Throws imx::Error naming the file, page and field for anything
// not read (colour, 1/4/12/24-bit samples, pages that disagree, corrupt or lying data).
VolumeData read_tiff(const std::filesystem::path& path, int frame = 0, int channel = 0);

// The grid, storage type, placement and time points, from the tags and descriptions alone.
VolumeHeader read_tiff_header(const std::filesystem::path& path);

// crop(read_tiff(path, frame, channel), box), decoding only the box's pages, and in them only
// the strips or tiles holding its rows.
VolumeData read_tiff_region(const std::filesystem::path& path, const VoxelBox& box, int frame,
                            int channel = 0);

}  // namespace imx::detail
