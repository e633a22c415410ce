#include "io/polygon_check.hpp"

#include <charconv>
#include <fstream>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/header_text.hpp"

namespace imx::detail {
namespace {

// The next whitespace-separated word of `s` from `at`, empty at the end.
std::string_view next_word(std::string_view s, size_t& at) {
  while (at < s.size() && std::isspace(static_cast<unsigned char>(s[at]))) ++at;
  size_t start = at;
  while (at < s.size() && !std::isspace(static_cast<unsigned char>(s[at]))) ++at;
  return s.substr(start, at - start);
}

// A whole-word unsigned integer, or false.
bool parse_count(std::string_view word, uint64_t& v) {
  auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
  return ec == std::errc() && end == word.data() + word.size();
}

}  // namespace

void check_obj_polygons(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    // assimp's OBJ parser takes a NUL for the end of its buffer and reads on past it.
    if (line.find('\0') != std::string::npos)
      throw Error(fmt::format("{}: line {}: a NUL byte (an OBJ file is text)", file.string(),
                              number));
    size_t at = 0;
    if (next_word(line, at) != "f") continue;
    size_t corners = 0;
    while (!next_word(line, at).empty()) ++corners;
    if (corners > kMaxPolygonCorners)
      throw Error(fmt::format("{}: line {}: a face with {} corners (at most {})", file.string(),
                              number, corners, kMaxPolygonCorners));
  }
}

void check_off(const std::filesystem::path& file) {
  const std::string what = file.string();
  std::ifstream in(file, std::ios::binary);
  std::string line;
  // Words of the file after the "OFF" keyword, skipping comments.
  std::string_view words;
  size_t at = 0, line_number = 0;
  auto word = [&]() -> std::string_view {
    while (true) {
      std::string_view w = next_word(words, at);
      if (!w.empty() && w[0] != '#') return w;
      if (!w.empty()) at = words.size();  // a comment runs to the end of the line
      if (!std::getline(in, line)) return {};
      ++line_number;
      words = line;
      at = 0;
    }
  };
  auto count = [&](const char* name) {
    uint64_t v = 0;
    std::string_view w = word();
    if (!parse_count(w, v))
      throw Error(fmt::format("{}: line {}: {} '{}' is not a non-negative integer", what,
                              line_number, name, shown(w)));
    return v;
  };
  std::string_view keyword = word();
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF")
    throw Error(fmt::format("{}: does not start with OFF", what));
  if (keyword != "OFF")
    return;  // COFF, NOFF, 4OFF...: variants with more columns; assimp checks those itself
  const uint64_t vertices = count("the vertex count"), faces = count("the face count");
  count("the edge count");
  for (uint64_t v = 0; v < vertices * 3; ++v)
    if (word().empty())
      throw Error(fmt::format("{}: ends inside vertex {} of {}", what, v / 3, vertices));
  for (uint64_t f = 0; f < faces; ++f) {
    const uint64_t corners = count("a face's corner count");
    if (corners > kMaxPolygonCorners)
      throw Error(fmt::format("{}: face {} has {} corners (at most {})", what, f, corners,
                              kMaxPolygonCorners));
    for (uint64_t c = 0; c < corners; ++c) {
      uint64_t index = count("a vertex index");
      if (index >= vertices)
        throw Error(fmt::format("{}: face {} uses vertex {}, but the file has {} vertices", what, f,
                                index, vertices));
    }
    // Anything after the indices (a face colour) is on the same line.
    at = words.size();
  }
}

}  // namespace imx::detail
