// TRX tractograms (https://github.com/tee-ar-ex/trx-spec): a zip archive (stored or deflated
// members) or the same tree unpacked in a folder, read as trx-python's trx_file_memmap reads it.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "intermix/streamlines.hpp"

namespace imx::detail {

// Reads `file` (a .trx archive, or a folder holding header.json): positions (RAS mm, float16,
// float32 or float64) become world LPS points; dpv arrays point_values, dps arrays
// streamline_values (one per column, named NAME_0, NAME_1, .. when an array has several);
// groups their members, with the colour of a dpg/GROUP/*colo(u)r*.3.* array if there is one.
// Offsets may hold NB_STREAMLINES entries or NB_STREAMLINES + 1 (the last, NB_VERTICES).
// Streamlines with fewer than 2 points or non-finite points are dropped, with a line in `notes`
// (as are members the reader ignores). Throws imx::Error naming the file and the member when a
// size disagrees with header.json's counts and the dtype in the member's name, offsets do not
// ascend, a header key is missing, or an index is out of range; imx::FileError when it cannot
// be read.
Streamlines read_trx(const std::filesystem::path& file, std::vector<std::string>& notes);

}  // namespace imx::detail
