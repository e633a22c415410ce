// How a TIFF is known before libtiff opens it: its first bytes, and a folder of TIFF slices.
// Here, not in src/io/tiff, because the DICOM folder sniff asks too (a TIFF stack is no series).
#pragma once
#include <filesystem>
#include <string_view>

namespace imx::detail {

// Whether `head` (a file's first bytes) starts a classic TIFF or a BigTIFF, in either byte order,
// and is not a DICOM file that is also a TIFF ("DICM" at byte 128: DICOM's dual-personality
// files are read as DICOM).
bool is_tiff_head(std::string_view head);

// Whether `path` ends in .tif or .tiff, in any case.
bool has_tiff_extension(const std::filesystem::path& path);

// Whether `dir` is a TIFF stack: a folder holding at least one file, every one of whose regular
// files (hidden ones aside: .DS_Store) is named .tif or .tiff. Subfolders are not looked into.
bool is_tiff_folder(const std::filesystem::path& dir);

}  // namespace imx::detail
