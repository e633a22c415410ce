#include "io/mesh/polygon_check.hpp"

#include <charconv>
#include <fstream>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/input_file.hpp"

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
  std::ifstream in = open_input_stream(file);
  std::string line;
  uint64_t vertices = 0, faces = 0;
  size_t highest_line = 0;  // the line of the face naming the highest positive vertex index
  uint64_t highest = 0;     // that index
  for (size_t number = 1; std::getline(in, line); ++number) {
    // assimp's OBJ parser takes a NUL for the end of its buffer and reads on past it.
    if (line.find('\0') != std::string::npos)
      throw Error(
          fmt::format("{}: line {}: a NUL byte (an OBJ file is text)", file.string(), number));
    size_t at = 0;
    const std::string_view keyword = next_word(line, at);
    // assimp joins the name to the OBJ's folder, absolute or not ("mesh//etc/x.mtl").
    if (keyword == "mtllib") {
      const std::string_view name = trim(std::string_view(line).substr(at));
      if (!name.empty() && name[0] == '/')
        throw Error(fmt::format(
            "{}: line {}: mtllib '{}' is an absolute path; material files are named relative "
            "to the OBJ's folder",
            file.string(), number, shown(name)));
    }
    if (keyword == "v") ++vertices;
    if (keyword != "f") continue;
    ++faces;
    size_t corners = 0;
    for (std::string_view corner = next_word(line, at); !corner.empty();
         corner = next_word(line, at)) {
      ++corners;
      // The vertex index before any '/': 1-based, or negative counting back from the last vertex.
      const std::string_view index = corner.substr(0, corner.find('/'));
      int64_t i = 0;
      auto [end, ec] = std::from_chars(index.data(), index.data() + index.size(), i);
      if (ec != std::errc() || end != index.data() + index.size()) continue;  // '\' and the like
      if (i == 0 || (i < 0 && static_cast<uint64_t>(-i) > vertices))
        throw Error(fmt::format("{}: line {}: face corner {} names vertex {} of the {} before it",
                                file.string(), number, shown(corner), i, vertices));
      if (i > 0 && static_cast<uint64_t>(i) > highest) {
        highest = static_cast<uint64_t>(i);
        highest_line = number;
      }
    }
    if (corners > kMaxPolygonCorners)
      throw Error(fmt::format("{}: line {}: a face with {} corners (at most {})", file.string(),
                              number, corners, kMaxPolygonCorners));
  }
  if (vertices == 0)
    throw Error(fmt::format("{}: no vertices ('v' lines): not an OBJ mesh", file.string()));
  if (faces == 0)
    throw Error(
        fmt::format("{}: {} vertices and no faces ('f' lines): a point cloud, not a "
                    "surface",
                    file.string(), vertices));
  if (highest > vertices)
    throw Error(fmt::format("{}: line {}: a face names vertex {}; the file has {}", file.string(),
                            highest_line, highest, vertices));
}

// OFF's keyword: [ST][C][N][4]OFF (texture coordinates, colours, normals, homogeneous
// coordinates: more columns per vertex line). nOFF, which changes the dimension, is refused.
bool is_off_keyword(std::string_view k) {
  for (std::string_view prefix : {"ST", "C", "N", "4"})
    if (k.substr(0, prefix.size()) == prefix) k.remove_prefix(prefix.size());
  return k == "OFF";
}

void check_off(const std::filesystem::path& file) {
  const std::string what = file.string();
  std::ifstream in = open_input_stream(file, what);
  std::string line;
  size_t line_number = 0, at = 0;
  // The next line with a word on it. assimp reads a vertex or a face per line and has no
  // comments there, so a comment is allowed only before the counts.
  auto next_line = [&](bool comments_allowed) {
    while (std::getline(in, line)) {
      ++line_number;
      // assimp's parsers take a NUL for the end of their buffer and read on past it.
      if (line.find('\0') != std::string::npos)
        throw Error(
            fmt::format("{}: line {}: a NUL byte (an OFF file is text)", what, line_number));
      at = 0;
      std::string_view first = next_word(line, at);
      at = 0;
      if (first.empty()) continue;
      if (first[0] != '#') return true;
      if (!comments_allowed)
        throw Error(fmt::format("{}: line {}: a comment inside the vertex or face lists", what,
                                line_number));
    }
    return false;
  };
  auto word = [&]() { return next_word(line, at); };
  if (!next_line(true) || !is_off_keyword(word()))
    throw Error(fmt::format("{}: does not start with OFF (or COFF, NOFF, 4OFF, STOFF)", what));
  uint64_t counts[3] = {};
  const char* count_names[3] = {"the vertex count", "the face count", "the edge count"};
  for (int c = 0; c < 3; ++c) {
    std::string_view w = word();
    while (w.empty() && next_line(true)) w = word();
    if (!parse_count(w, counts[c]))
      throw Error(fmt::format("{}: line {}: {} '{}' is not a non-negative integer", what,
                              line_number, count_names[c], shown(w)));
  }
  const uint64_t vertices = counts[0], faces = counts[1];
  for (uint64_t v = 0; v < vertices; ++v) {
    if (!next_line(false))
      throw Error(fmt::format("{}: ends before vertex {} of {}", what, v, vertices));
    int numbers = 0;
    while (numbers < 3 && !word().empty()) ++numbers;
    if (numbers < 3)
      throw Error(
          fmt::format("{}: line {}: vertex {} has {} coordinates (a vertex is one line "
                      "of at least 3)",
                      what, line_number, v, numbers));
  }
  for (uint64_t f = 0; f < faces; ++f) {
    if (!next_line(false))
      throw Error(fmt::format("{}: ends before face {} of {}", what, f, faces));
    uint64_t corners = 0;
    std::string_view w = word();
    if (!parse_count(w, corners))
      throw Error(
          fmt::format("{}: line {}: face {}'s corner count '{}' is not a non-negative "
                      "integer",
                      what, line_number, f, shown(w)));
    // assimp's OFF reader takes a face of 0 corners off its count but not off its face array (a
    // crash, found by fuzz_mesh), and refuses more than 9 as "zero indices": both named here.
    if (corners == 0 || corners > kMaxOffCorners)
      throw Error(
          fmt::format("{}: line {}: face {} has {} corners; an OFF face is read with 1 to "
                      "{} (split larger polygons)",
                      what, line_number, f, corners, kMaxOffCorners));
    // A face is one line: its indices, then anything (a face colour) that assimp skips.
    for (uint64_t c = 0; c < corners; ++c) {
      uint64_t index = 0;
      w = word();
      if (!parse_count(w, index))
        throw Error(
            fmt::format("{}: line {}: face {}: vertex index '{}' is not a non-negative "
                        "integer (a face is one line)",
                        what, line_number, f, shown(w)));
      if (index >= vertices)
        throw Error(fmt::format("{}: face {} uses vertex {}, but the file has {} vertices", what, f,
                                index, vertices));
    }
  }
  while (std::getline(in, line))
    if (line.find('\0') != std::string::npos)
      throw Error(fmt::format("{}: a NUL byte after the faces (an OFF file is text)", what));
}

}  // namespace imx::detail
