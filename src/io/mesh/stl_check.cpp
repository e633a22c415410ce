#include "io/mesh/stl_check.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/input_file.hpp"

namespace imx::detail {
namespace {

constexpr uint64_t kBinaryHeader = 84;  // 80 bytes of text, then the uint32 triangle count
constexpr uint64_t kBinaryTriangle = 50;

// ASCII STL as assimp tells it: "solid" first and "facet" in the first 500 bytes (a binary
// header may begin "solid" too: SolidWorks writes such files).
bool is_ascii(std::string_view head) {
  return head.substr(0, 5) == "solid" && head.find("facet") != std::string_view::npos;
}

void check_ascii(std::ifstream& in, const std::filesystem::path& file) {
  uint64_t vertices = 0;
  size_t line_number = 0, last_facet = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    const std::string_view word = std::string_view(line).substr(first, 6);
    if (word.substr(0, 5) == "facet") {
      if (vertices % 3 != 0)
        throw Error(fmt::format("{}: line {}: a facet after {} vertices: facets hold 3 each",
                                file.string(), line_number, vertices));
      last_facet = line_number;
    }
    if (word == "vertex") ++vertices;
  }
  if (vertices == 0)
    throw Error(fmt::format("{}: an ASCII STL with no vertices: no triangles", file.string()));
  if (vertices % 3 != 0)
    throw Error(fmt::format("{}: line {}: the last facet has {} vertices, not 3", file.string(),
                            last_facet, vertices % 3));
}

}  // namespace

void check_stl(const std::filesystem::path& file) {
  std::ifstream in = open_input_stream(file);
  std::string head(kBinaryHeader, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  std::string more(416, '\0');  // ASCII files say "facet" soon after their name
  in.read(more.data(), static_cast<std::streamsize>(more.size()));
  more.resize(static_cast<size_t>(in.gcount()));
  if (is_ascii(head + more)) {
    in.clear();
    in.seekg(0);
    check_ascii(in, file);
    return;
  }
  const uint64_t size = std::filesystem::file_size(file);
  if (size < kBinaryHeader)
    throw Error(
        fmt::format("{}: {} bytes: shorter than a binary STL's 84-byte header, and not "
                    "ASCII STL (\"solid\" ... \"facet\")",
                    file.string(), size));
  uint32_t count = 0;
  std::memcpy(&count, head.data() + 80, sizeof count);  // little-endian, as every STL writer
  const uint64_t expected = kBinaryHeader + kBinaryTriangle * count;
  if (count == 0) throw Error(fmt::format("{}: a binary STL of 0 triangles", file.string()));
  // Longer is accepted, as assimp and VTK do (some writers pad); shorter would read past the end.
  if (size < expected)
    throw Error(fmt::format("{}: a binary STL of {} triangle{} needs {} bytes; the file has {}",
                            file.string(), count, count == 1 ? "" : "s", expected, size));
}

}  // namespace imx::detail
