// Reading a small text file whole, with a size bound, for preset and colour-map files.
#pragma once
#include <cstddef>
#include <filesystem>
#include <string>

namespace imx {

// The bytes of `file`; throws imx::Error naming it when it is not a readable regular file or is
// larger than `max_bytes` (a colour map is kilobytes; a bound keeps a wrong file from filling
// memory).
std::string read_text_file(const std::filesystem::path& file, size_t max_bytes);

}  // namespace imx
