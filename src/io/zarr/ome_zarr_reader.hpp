// OME-Zarr (OME-NGFF 0.4) volumes: a Zarr v2 group whose .zattrs "multiscales" names its
// resolution levels (arrays) and their axes, scale and translation (docs/big_data.md, "OME-Zarr").
#pragma once
#include <filesystem>

#include "intermix/volume.hpp"

namespace imx::detail {

// Whether `dir` is a folder holding Zarr v2 group or array metadata (.zgroup, .zattrs, .zarray).
bool is_zarr_folder(const std::filesystem::path& dir);

// The grid of resolution level `level` (0: the finest) at time point `frame` and channel
// `channel`: the array's last three axes z, y, x become k, j, i. Throws imx::Error naming the
// file and field for anything not read (v3, Fortran order, filters, other codecs).
VolumeData read_ome_zarr(const std::filesystem::path& dir, int level = 0, int frame = 0,
                         int channel = 0);

// Level 0's grid, type and placement; frames counts its time points.
VolumeHeader read_ome_zarr_header(const std::filesystem::path& dir);

}  // namespace imx::detail
