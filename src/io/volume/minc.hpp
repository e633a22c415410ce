// MINC volumes (.mnc): MINC-2 (HDF5) read through libhdf5 as nibabel.minc2 reads it; MINC-1
// (netCDF classic) is recognised and refused with the way to convert it.
#pragma once
#include <filesystem>
#include <string_view>

#include "intermix/volume.hpp"

namespace imx::detail {

// Frame `frame` (of the "time" dimension, if any) of a MINC-2 file. The voxel axes i, j, k are
// the image's spatial dimensions in the file's order (slowest first: zspace, yspace, xspace for
// the usual order), as nibabel's array axes are; placed by nibabel's Minc2File.get_affine
// (direction cosines times step, origin = cosines times start), RAS converted to LPS. Integer
// voxels are clipped to valid_range and mapped onto image-min .. image-max (per slice when those
// vary along the image's first dimensions), giving float32, except where that mapping is the
// identity for u8, i16 and u16 data, which keep their type; float data is read as it is (double
// becomes float32). Throws imx::Error naming the file and the field: MINC-1 files (with the
// conversion command), irregular spacing, fewer or more than 3 spatial dimensions, dimensions
// other than xspace/yspace/zspace and time, a valid_range outside the type's.
VolumeData read_minc(const std::filesystem::path& file, int frame = 0);

// read_minc(file)'s dims, storage type and placement, with the frame count and, for several
// frames, each frame's time from the time dimension's step. Reads no voxels.
VolumeHeader read_minc_header(const std::filesystem::path& file);

// crop(read_minc(file, frame), box), reading only the box's hyperslab from the file.
VolumeData read_minc_region(const std::filesystem::path& file, const VoxelBox& box, int frame = 0);

// Whether a file starting with `first_bytes` is MINC-2 (HDF5's signature at offset 0) or MINC-1
// (netCDF classic: "CDF\x01" or "CDF\x02"; read_minc refuses it with a message saying so).
bool is_minc(std::string_view first_bytes);

// The reads behind read_minc_header and read_minc(_region) in this process (minc2_reader.cpp):
// libhdf5 1.10 is not safe on hostile files (fuzz_minc: a use-after-free under H5Aexists), so
// the public functions run these in a child process (minc_isolated.cpp).
VolumeHeader read_minc_header_in_process(const std::filesystem::path& file);
VoxelStorage read_minc_box_in_process(const std::filesystem::path& file, int frame,
                                      const VoxelBox& box);

}  // namespace imx::detail
