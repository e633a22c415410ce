// The string values of legacy VTK files: VTK's %XX escapes in ASCII, length prefixes in BINARY.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace imx::detail {

// An ASCII string value with its %XX escapes (vtkDataWriter's for spaces, '%' and other special
// bytes) decoded.
std::string unescape_vtk_string(std::string_view text);

// The BINARY string value at bytes[pos]: its length first, big-endian in 1, 2, 4 or 8 bytes as the
// top two bits of the first byte say (11, 10, 01, 00), then its bytes; `pos` moves past it.
// nullopt, `pos` unchanged, when the file ends inside it.
std::optional<std::string> read_vtk_binary_string(std::string_view bytes, size_t& pos);

}  // namespace imx::detail
