// A structural check of a whole DICOM file before GDCM parses it: Debian's GDCM asserts (aborts
// the process) on some malformed elements and allocates whatever length an element claims.
#pragma once
#include <filesystem>
#include <string>

namespace imx::detail {

// Walks every element (nested sequences and items, encapsulated pixel fragments included) and
// returns "" when each one is well formed and lies inside the file, else what is wrong (for a
// message). Deflated data sets are refused (they cannot be checked without inflating).
std::string check_dicom_structure(const std::filesystem::path& file);

}  // namespace imx::detail
