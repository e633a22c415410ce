// TrackVis .trk tractograms (versions 1 and 2; 3 read as 2, as nibabel does), read as
// nibabel.streamlines.load reads them.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "intermix/streamlines.hpp"

namespace imx::detail {

// The streamlines of `file` in world LPS mm: the 1000-byte header (its byte order found from
// hdr_size), then per streamline an int32 point count, the points (x y z and n_scalars float32
// each, in voxmm, mapped to RAS+ mm as trk_space.hpp says) and n_properties float32.
// Scalars become point_values and properties streamline_values, named from scalar_name /
// property_name (nibabel's "name\0N" packing of N values; a name of N > 1 values gives arrays
// "name[0]" .. "name[N-1]"; unnamed values are "scalars" / "properties", names trimmed of
// blanks). n_count 0 reads to the end of the file. Streamlines of fewer than 2 points, or with a
// coordinate that is not finite, are dropped, with their values, and said in `notes` (with
// other choices: a missing vox_to_ras or voxel order, bytes left after n_count streamlines).
// Throws imx::Error naming the file and the field: not TRACK, hdr_size not 1000 in either byte
// order, a version other than 1, 2 or 3, a voxel order, vox_to_ras or voxel size trk_space.hpp
// refuses, negative counts, n_count more streamlines than the file holds, a point count that
// overruns the file, a malformed scalar or property name.
Streamlines read_trk(const std::filesystem::path& file, std::vector<std::string>& notes);

}  // namespace imx::detail
