// DSI Studio TinyTrack (.tt.gz): a gzip-compressed MATLAB v4 file whose matrix "track" holds the
// streamlines, each a start voxel and 8-bit steps in 1/32 voxel, and whose "trans_to_mni" (else
// "dimension" and "voxel_size") places those voxels in RAS mm.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "intermix/streamlines.hpp"

namespace imx::detail {

// The streamlines of a .tt.gz (or uncompressed .tt) file in LPS mm: voxel coordinates through
// trans_to_mni read row by row (as NiiVue and DSI Studio do), else through the voxel-to-RAS
// matrix DSI Studio writes for its own volumes (from dimension and voxel_size), then x and y
// negated. Inflates no more than deflate's ratio and the memory budget allow; every matrix
// header and every streamline record is checked against the bytes that are left. `notes` gets
// a line for each streamline left out (fewer than 2 points, points that are not finite), for a
// placement without trans_to_mni, and for matrices left unread.
Streamlines read_tt(const std::filesystem::path& file, std::vector<std::string>& notes);

}  // namespace imx::detail
