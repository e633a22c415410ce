// OME-Zarr volumes: a Zarr group whose "multiscales" names its resolution levels (arrays) and their
// axes, scale and translation: NGFF 0.4 (Zarr v2, .zattrs) or 0.5 (Zarr v3, zarr.json "ome")
// (docs/big_data.md, "OME-Zarr").
#pragma once
#include <filesystem>
#include <vector>

#include "intermix/volume.hpp"
#include "io/zarr/ome_channels.hpp"

namespace imx::detail {

// Whether `dir` is a folder holding Zarr group or array metadata (.zgroup, .zattrs, .zarray,
// zarr.json).
bool is_zarr_folder(const std::filesystem::path& dir);

// The grid of resolution level `level` (0: the finest) at time point `frame` and channel
// `channel`: the array's last three axes z, y, x become k, j, i. Throws imx::Error naming the
// file and field for anything not read (Fortran order, filters, other codecs).
VolumeData read_ome_zarr(const std::filesystem::path& dir, int level = 0, int frame = 0,
                         int channel = 0);
// The voxels of `box` (inside the level's grid) of the same: only the chunks it touches are read.
VolumeData read_ome_zarr_region(const std::filesystem::path& dir, const VoxelBox& box,
                                int level = 0, int frame = 0, int channel = 0);

// Level `level`'s grid, type and placement; frames counts its time points.
VolumeHeader read_ome_zarr_header(const std::filesystem::path& dir, int level = 0);
// How many resolution levels the image has (multiscales[0].datasets).
int read_ome_zarr_level_count(const std::filesystem::path& dir);

// One entry per channel of the image (one when it has no channel axis): its omero metadata.
std::vector<OmeChannel> read_ome_zarr_channels(const std::filesystem::path& dir);

}  // namespace imx::detail
