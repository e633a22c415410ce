// AFNI datasets: a .HEAD text header with a .BRIK (or .BRIK.gz) of voxels, in any view
// (+orig, +acpc, +tlrc): the reader behind read_volume for them.
#pragma once
#include <filesystem>
#include <string_view>

#include "intermix/volume.hpp"

namespace imx::detail {

// Reads sub-brick `frame` of the dataset named by its .HEAD or its .BRIK(.gz), as nibabel's
// brikhead reads it: byte, short or float sub-bricks (one type for all), in the byte order of
// BYTEORDER_STRING, times BRICK_FLOAT_FACS (a factor of 0 means 1; any factor makes float32
// voxels), placed by IJK_TO_DICOM_REAL (else ORIGIN, DELTA and ORIENT_SPECIFIC), which is LPS
// already. The BRIK must hold exactly the bytes the header describes. Throws imx::Error naming
// the file and the attribute at fault.
VolumeData read_afni(const std::filesystem::path& file, int frame = 0);

// read_afni's dims, type and placement, with one frame per sub-brick, labelled by BRICK_LABS
// and, for a time series (TAXIS_FLOATS' step in s or ms), each frame's time. Reads the HEAD.
VolumeHeader read_afni_header(const std::filesystem::path& file);

// crop(read_afni(file, frame), box), reading only the box's bytes of an uncompressed BRIK.
VolumeData read_afni_region(const std::filesystem::path& file, const VoxelBox& box, int frame = 0);

// Whether `first_bytes` (the start of a file) look like an AFNI HEAD: blank lines, then
// "type = string-attribute" (or integer-, float-) as AFNI writes its first attribute.
bool is_afni_head(std::string_view first_bytes);

}  // namespace imx::detail
