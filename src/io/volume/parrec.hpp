// Philips PAR/REC volumes (.PAR header text + .REC slices, versions 4, 4.1 and 4.2), read as
// nibabel.parrec reads them with its defaults (lax slice sorting, 'dv' scaling, scanner origin).
#pragma once
#include <filesystem>
#include <string_view>

#include "intermix/volume.hpp"

namespace imx::detail {

// Frame `frame` (a volume of nibabel's fourth axis: dynamic, echo, diffusion direction, image
// type...) of a PAR/REC pair; `file` is either of the two, its partner found beside it with the
// extension in either case. Slices are gathered into volumes as nibabel does (the n-th time a
// slice number appears in the table, it belongs to volume n), scaled by the slice's rescale
// slope and intercept to float32 (nibabel's default 'dv' values), placed by nibabel's
// PARRECHeader.get_affine (origin at the scanner's isocentre), RAS converted to LPS. Throws
// imx::Error naming the file and the field for what nibabel refuses: an unsupported version, a
// truncated series, slice properties that vary, a REC shorter than the table needs.
VolumeData read_parrec(const std::filesystem::path& file, int frame = 0);

// read_parrec(file)'s dims, type (float32), placement and frame count, with a label per frame
// when there are several (b value and gradient direction, echo time, dynamic's start time, image
// type, trigger time: those that differ between frames). Only the PAR text is read; the REC
// must be there and long enough.
VolumeHeader read_parrec_header(const std::filesystem::path& file);

// crop(read_parrec(file, frame), box), reading only the box's rows of the REC.
VolumeData read_parrec_region(const std::filesystem::path& file, const VoxelBox& box,
                              int frame = 0);

// Whether a file starting with `first_bytes` is a PAR header (its "DATA DESCRIPTION FILE" line).
bool is_parrec_header(std::string_view first_bytes);

}  // namespace imx::detail
