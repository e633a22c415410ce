#include "io/mesh/vtk_strings.hpp"

#include <charconv>
#include <cstdint>

namespace imx::detail {

std::string unescape_vtk_string(std::string_view text) {
  std::string out;
  for (size_t c = 0; c < text.size(); ++c) {
    int code = 0;
    const char* hex = text.data() + c + 1;
    if (text[c] == '%' && c + 2 < text.size() &&
        std::from_chars(hex, hex + 2, code, 16).ptr == hex + 2) {
      out += static_cast<char>(code);
      c += 2;
    } else {
      out += text[c];
    }
  }
  return out;
}

std::optional<std::string> read_vtk_binary_string(std::string_view bytes, size_t& pos) {
  if (pos >= bytes.size()) return std::nullopt;
  const auto first = static_cast<uint8_t>(bytes[pos]);
  const size_t size = first >> 6 == 3 ? 1 : first >> 6 == 2 ? 2 : first >> 6 == 1 ? 4 : 8;
  if (bytes.size() - pos < size) return std::nullopt;
  uint64_t length = first & 0x3f;
  for (size_t b = 1; b < size; ++b) length = (length << 8) | static_cast<uint8_t>(bytes[pos + b]);
  if (length > bytes.size() - pos - size) return std::nullopt;
  std::string out(bytes.substr(pos + size, static_cast<size_t>(length)));
  pos += size + static_cast<size_t>(length);
  return out;
}

}  // namespace imx::detail
