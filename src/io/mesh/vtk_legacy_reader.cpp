// Legacy VTK polydata (.vtk), read by hand: intermix needs its points, polygons, strips and
// point data, and every count must be checked against the file before anything is allocated.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <string_view>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/mesh/mesh_space.hpp"
#include "io/mesh/polydata.hpp"
#include "io/mesh/vtk_strings.hpp"
#include "io/streams/byte_cursor.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {
namespace {

constexpr size_t kMaxLine = 4096;
constexpr uint64_t kMaxValues = uint64_t{1} << 31;

// Bytes of one value of a legacy type name in BINARY files (0: not a type intermix reads).
int type_bytes(std::string_view type, bool& is_float, bool& is_signed) {
  static const std::map<std::string_view, std::pair<int, int>> table = {
      // bytes, kind (0 unsigned, 1 signed, 2 float)
      {"unsigned_char", {1, 0}},  {"char", {1, 1}},
      {"vtktypeuint8", {1, 0}},   {"vtktypeint8", {1, 1}},
      {"unsigned_short", {2, 0}}, {"short", {2, 1}},
      {"vtktypeuint16", {2, 0}},  {"vtktypeint16", {2, 1}},
      {"unsigned_int", {4, 0}},   {"int", {4, 1}},
      {"vtktypeuint32", {4, 0}},  {"vtktypeint32", {4, 1}},
      {"vtkIdType", {4, 1}},  // written as int for compatibility
      {"unsigned_long", {8, 0}},  {"long", {8, 1}},
      {"vtktypeuint64", {8, 0}},  {"vtktypeint64", {8, 1}},
      {"float", {4, 2}},          {"double", {8, 2}},
      {"vtktypefloat32", {4, 2}}, {"vtktypefloat64", {8, 2}},
  };
  auto it = table.find(type);
  if (it == table.end()) return 0;
  is_float = it->second.second == 2;
  is_signed = it->second.second == 1;
  return it->second.first;
}

class LegacyReader {
 public:
  LegacyReader(const std::string& bytes, std::string what)
      : bytes_(bytes), what_(std::move(what)) {}

  [[noreturn]] void fail(const std::string& why) const {
    throw Error(fmt::format("{}: {}", what_, why));
  }

  bool binary = false;

  // The next non-blank line, or nullopt at the end of the file.
  std::optional<std::string_view> line() {
    while (pos_ < bytes_.size()) {
      const size_t eol = std::min(bytes_.find('\n', pos_), bytes_.size());
      if (eol - pos_ > kMaxLine)
        fail(fmt::format("a line at byte {} is over {} bytes where a keyword belongs", pos_,
                         kMaxLine));
      std::string_view l = trim(std::string_view(bytes_).substr(pos_, eol - pos_));
      pos_ = std::min(eol + 1, bytes_.size());
      if (!l.empty()) return l;
    }
    return std::nullopt;
  }

  // The raw first line (the version), the title line, as they are.
  std::string_view raw_line(const char* field) {
    const size_t eol = bytes_.find('\n', pos_);
    if (eol == std::string::npos || eol - pos_ > kMaxLine)
      fail(fmt::format("{} is not a line of at most {} bytes", field, kMaxLine));
    std::string_view l = std::string_view(bytes_).substr(pos_, eol - pos_);
    pos_ = eol + 1;
    return l;
  }

  // Steps back to the start of `l`, a line line() just gave.
  void unread(std::string_view l) { pos_ = static_cast<size_t>(l.data() - bytes_.data()); }

  // Whether the next non-blank text starts with `word` (nothing is consumed).
  bool next_is(std::string_view word) const {
    size_t p = pos_;
    while (p < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[p]))) ++p;
    return std::string_view(bytes_).substr(p).starts_with(word);
  }

  // `n` values of legacy type `type` for `field`, as doubles (kept only when `keep`).
  std::vector<double> values(std::string_view type, uint64_t n, const std::string& field,
                             bool keep = true) {
    bool is_float = false, is_signed = false;
    const int bytes = type_bytes(type, is_float, is_signed);
    if (bytes == 0)
      fail(fmt::format("{}: data type '{}' is not a numeric type intermix reads", field,
                       shown(type)));
    if (n > kMaxValues) fail(fmt::format("{}: {} values are more than intermix reads", field, n));
    const uint64_t rest = bytes_.size() - pos_;
    // Each value takes its size in binary, a digit and a separator in text.
    if (binary ? n * static_cast<uint64_t>(bytes) > rest : n > rest / 2 + 1)
      fail(fmt::format("{}: {} values of {} are more than the rest of the file ({} bytes) holds",
                       field, n, type, rest));
    std::vector<double> out;
    if (keep) {
      check_memory(n * 8, fmt::format("{} ({})", what_, field));
      out.reserve(static_cast<size_t>(n));
    }
    if (binary) {
      ByteCursor in(std::string_view(bytes_).substr(pos_), what_, true);
      for (uint64_t i = 0; keep && i < n; ++i)
        out.push_back(binary_value(in, bytes, is_float, is_signed));
      pos_ += static_cast<size_t>(n) * static_cast<size_t>(bytes);
      return out;
    }
    for (uint64_t i = 0; i < n; ++i) {
      while (pos_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
      size_t end = pos_;
      while (end < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[end]))) ++end;
      const char* b = bytes_.data() + pos_;
      const char* e = bytes_.data() + end;
      if (b < e && *b == '+') ++b;
      double v = 0.0;
      auto r = std::from_chars(b, e, v);
      if (b == e || r.ec != std::errc() || r.ptr != e)
        fail(fmt::format("{}: value {} '{}' is not a number", field, i,
                         shown(std::string_view(bytes_).substr(pos_, end - pos_))));
      if (!is_float && v != std::floor(v))
        fail(fmt::format("{}: value {} '{:g}' is not an integer", field, i, v));
      if (keep) out.push_back(v);
      pos_ = end;
    }
    return out;
  }

  // `n` strings of a string array for `field`: in ASCII a line each (vtk_strings.hpp).
  std::vector<std::string> strings(uint64_t n, const std::string& field) {
    if (n > bytes_.size() - pos_ + 1)  // each string takes a byte at least
      fail(fmt::format("{}: {} strings are more than the rest of the file holds", field, n));
    std::vector<std::string> out;
    for (uint64_t i = 0; i < n; ++i) {
      if (pos_ >= bytes_.size()) fail(fmt::format("{}: the file ends before string {}", field, i));
      std::optional<std::string> s = binary ? read_vtk_binary_string(bytes_, pos_)
                                            : unescape_vtk_string(trim(raw_line("a string")));
      if (!s) fail(fmt::format("{}: the file ends inside string {}", field, i));
      out.push_back(std::move(*s));
    }
    return out;
  }

 private:
  static double binary_value(ByteCursor& in, int bytes, bool is_float, bool is_signed) {
    if (is_float) return bytes == 4 ? in.read<float>("a value") : in.read<double>("a value");
    switch (bytes) {
      case 1:
        return is_signed ? in.read<int8_t>("a value") : in.read<uint8_t>("a value");
      case 2:
        return is_signed ? in.read<int16_t>("a value") : in.read<uint16_t>("a value");
      case 4:
        return is_signed ? in.read<int32_t>("a value") : in.read<uint32_t>("a value");
      default:
        return is_signed ? static_cast<double>(in.read<int64_t>("a value"))
                         : static_cast<double>(in.read<uint64_t>("a value"));
    }
  }

  const std::string& bytes_;
  std::string what_;
  size_t pos_ = 0;
};

std::optional<uint64_t> count_word(std::string_view w) {
  std::optional<int64_t> v = parse_header_number<int64_t>(w);
  if (!v || *v < 0) return std::nullopt;
  return static_cast<uint64_t>(*v);
}

// "WORD n ..." with `words` count words: the counts from word 1 on.
std::vector<uint64_t> counts(const LegacyReader& in, const std::vector<std::string_view>& words,
                             size_t n, std::string_view line) {
  if (words.size() < n + 1)
    in.fail(fmt::format("'{}' has not the {} counts it needs", shown(line), n));
  std::vector<uint64_t> out;
  for (size_t i = 1; i <= n; ++i) {
    std::optional<uint64_t> c = count_word(words[i]);
    if (!c) in.fail(fmt::format("'{}': '{}' is not a count", shown(line), shown(words[i])));
    // Bounded here, so that counts times components cannot wrap around.
    if (*c > kMaxValues)
      in.fail(fmt::format("'{}': count {} is more than intermix reads ({})", shown(line), *c,
                          kMaxValues));
    out.push_back(*c);
  }
  return out;
}

// POLYGONS or TRIANGLE_STRIPS: the cells' vertex lists, in the classic layout (n size: each
// cell its count then its indices) or version 5's (offsets and connectivity arrays).
std::vector<std::vector<int64_t>> read_cells(LegacyReader& in, std::string_view line,
                                             bool version5) {
  const auto words = split_words(line);
  const std::vector<uint64_t> c = counts(in, words, 2, line);
  const std::string field(words[0]);
  std::vector<std::vector<int64_t>> cells;
  if (!version5) {
    const std::vector<double> data = in.values("int", c[1], field);
    size_t i = 0;
    for (uint64_t cell = 0; cell < c[0]; ++cell) {
      if (i >= data.size())
        in.fail(fmt::format("{}: the data ends inside cell {} of {}", field, cell, c[0]));
      const double k = data[i++];
      if (!(k >= 0.0 && k <= static_cast<double>(data.size() - i)))
        in.fail(
            fmt::format("{}: cell {} claims {} points, more than the data holds", field, cell, k));
      cells.emplace_back(data.begin() + static_cast<ptrdiff_t>(i),
                         data.begin() + static_cast<ptrdiff_t>(i + static_cast<size_t>(k)));
      i += static_cast<size_t>(k);
    }
    if (i != data.size())
      in.fail(fmt::format("{}: the cells use {} of the {} values the size claims", field, i,
                          data.size()));
    return cells;
  }
  auto array = [&](const char* name, uint64_t n) {
    const std::optional<std::string_view> l = in.line();
    const auto w = l ? split_words(*l) : std::vector<std::string_view>{};
    if (w.size() != 2 || w[0] != name)
      in.fail(fmt::format("{}: expected '{} type', got '{}'", field, name, shown(l.value_or(""))));
    return in.values(w[1], n, fmt::format("{} {}", field, name));
  };
  const std::vector<double> offsets = array("OFFSETS", c[0]);
  const std::vector<double> connectivity = array("CONNECTIVITY", c[1]);
  if (offsets.empty()) return cells;
  if (offsets.front() != 0.0 || offsets.back() != static_cast<double>(connectivity.size()))
    in.fail(fmt::format("{}: the offsets run from {} to {}, not 0 to {}", field, offsets.front(),
                        offsets.back(), connectivity.size()));
  for (size_t k = 0; k + 1 < offsets.size(); ++k) {
    if (!(offsets[k + 1] >= offsets[k] &&
          offsets[k + 1] <= static_cast<double>(connectivity.size())))
      in.fail(
          fmt::format("{}: offset {} ({}) is not between offset {} and the connectivity's "
                      "size {}",
                      field, k + 1, offsets[k + 1], k, connectivity.size()));
    cells.emplace_back(connectivity.begin() + static_cast<ptrdiff_t>(offsets[k]),
                       connectivity.begin() + static_cast<ptrdiff_t>(offsets[k + 1]));
  }
  return cells;
}

// VTK >= 8 follows arrays with "METADATA", "INFORMATION n" and key lines: information only.
void skip_metadata_lines(LegacyReader& in) {
  while (in.next_is("INFORMATION") || in.next_is("NAME") || in.next_is("DATA") ||
         in.next_is("COMPONENT_NAMES"))
    in.line();
}

void skip_metadata(LegacyReader& in) {
  if (!in.next_is("METADATA")) return;
  in.line();
  skip_metadata_lines(in);
}

// The attributes of POINT_DATA (kept: scalars, normals, field arrays) or CELL_DATA (skipped, or
// kept in `cell_arrays` where given), until the next section or the end. Returns the keyword
// line that ended them, if any.
std::optional<std::string_view> read_attributes(LegacyReader& in, uint64_t n, bool keep,
                                                PolyDataFile& out,
                                                std::vector<MeshPointData>* cell_arrays = nullptr) {
  std::vector<MeshPointData>& target = cell_arrays ? *cell_arrays : out.point_data;
  while (std::optional<std::string_view> line = in.line()) {
    const auto w = split_words(*line);
    const std::string_view key = w[0];
    const std::string name = w.size() > 1 ? std::string(w[1]) : std::string();
    auto need_words = [&](size_t k) {
      if (w.size() < k) in.fail(fmt::format("'{}' is missing a name or a type", shown(*line)));
    };
    if (key == "POINT_DATA" || key == "CELL_DATA" || key == "POINTS" || key == "POLYGONS" ||
        key == "TRIANGLE_STRIPS" || key == "VERTICES" || key == "LINES")
      return line;
    if (key == "SCALARS") {
      need_words(3);
      uint64_t components = 1;
      if (w.size() > 3) {
        std::optional<uint64_t> c = count_word(w[3]);
        if (!c || *c < 1 || *c > 4)
          in.fail(fmt::format("'{}': components '{}' is not 1 to 4", shown(*line), shown(w[3])));
        components = *c;
      }
      if (in.next_is("LOOKUP_TABLE")) in.line();
      std::vector<double> v = in.values(w[2], n * components, "SCALARS " + name, keep);
      if (keep) target.push_back({name, static_cast<int>(components), std::move(v)});
    } else if (key == "NORMALS") {
      need_words(3);
      const bool normals = keep && !cell_arrays;
      std::vector<double> v = in.values(w[2], n * 3, "NORMALS " + name, normals);
      if (normals) {
        out.mesh.normals.resize(static_cast<size_t>(n));
        for (size_t i = 0; i < out.mesh.normals.size(); ++i) {
          glm::dvec3 d(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
          const double len = glm::length(d);
          out.mesh.normals[i] =
              std::isfinite(len) && len > 0.0 ? glm::vec3(d / len) : glm::vec3(0.0f);
        }
      }
    } else if (key == "VECTORS") {
      need_words(3);
      in.values(w[2], n * 3, "VECTORS " + name, false);
    } else if (key == "TENSORS" || key == "TENSORS6") {
      need_words(3);
      in.values(w[2], n * (key == "TENSORS" ? 9 : 6), std::string(key) + " " + name, false);
    } else if (key == "TEXTURE_COORDINATES") {
      need_words(4);
      std::optional<uint64_t> dim = count_word(w[2]);
      if (!dim || *dim < 1 || *dim > 3) in.fail(fmt::format("'{}': bad dimension", shown(*line)));
      in.values(w[3], n * *dim, "TEXTURE_COORDINATES " + name, false);
    } else if (key == "COLOR_SCALARS" || key == "LOOKUP_TABLE") {
      need_words(3);
      std::optional<uint64_t> k = count_word(w[2]);
      if (!k || *k > 4096) in.fail(fmt::format("'{}': bad count", shown(*line)));
      const uint64_t count = key == "COLOR_SCALARS" ? n * *k : 4 * *k;
      in.values(in.binary ? "unsigned_char" : "float", count, std::string(key) + " " + name, false);
    } else if (key == "FIELD") {
      const std::optional<uint64_t> arrays = w.size() == 3 ? count_word(w[2]) : std::nullopt;
      if (!arrays || *arrays > 4096)
        in.fail(fmt::format("'{}' is not 'FIELD name arrays' (at most 4096)", shown(*line)));
      for (uint64_t a = 0; a < *arrays; ++a) {
        const std::optional<std::string_view> l = in.line();
        if (!l) in.fail(fmt::format("FIELD {}: the file ends before array {}", name, a));
        const auto aw = split_words(*l);
        if (aw.size() == 1 && aw[0] == "NULL_ARRAY") continue;
        if (aw.size() != 4)
          in.fail(
              fmt::format("FIELD {}: '{}' is not 'name components tuples type'", name, shown(*l)));
        const std::vector<uint64_t> ac = counts(in, {aw[0], aw[1], aw[2]}, 2, *l);
        if (ac[0] < 1 || ac[0] > 64)
          in.fail(fmt::format("FIELD {}: '{}' has {} components", name, shown(*l), ac[0]));
        if (aw[3] == "string" || aw[3] == "utf8_string") {
          const std::vector<std::string> strings =
              in.strings(ac[0] * ac[1], "FIELD array " + std::string(aw[0]));
          // 3D Slicer's coordinate system, as in a VTP's field data (vtp_reader.cpp).
          if (aw[0] == "SPACE" && strings.size() == 1) {
            if (strings[0] != "LPS" && strings[0] != "RAS")
              in.fail(
                  fmt::format("FIELD {}: SPACE is '{}', not LPS or RAS", name, shown(strings[0])));
            const MeshSpace space = strings[0] == "RAS" ? MeshSpace::ras : MeshSpace::lps;
            if (out.space && *out.space != space)
              in.fail(fmt::format("FIELD {}: SPACE is {}, but the title line says SPACE={}", name,
                                  strings[0], mesh_space_name(*out.space)));
            out.space = space;
          }
          skip_metadata(in);
          continue;
        }
        const bool kept = keep && ac[1] == n;
        std::vector<double> v =
            in.values(aw[3], ac[0] * ac[1], "FIELD array " + std::string(aw[0]), kept);
        if (kept) target.push_back({std::string(aw[0]), static_cast<int>(ac[0]), std::move(v)});
        skip_metadata(in);
      }
    } else if (key == "METADATA") {
      skip_metadata_lines(in);
    } else {
      in.fail(fmt::format("'{}' is not a point or cell attribute intermix reads", shown(*line)));
    }
  }
  return std::nullopt;
}

}  // namespace

PolyDataFile read_vtk_legacy(const std::filesystem::path& file, bool keep_lines) {
  const std::string bytes = read_file_bytes(file);
  LegacyReader in(bytes, file.string());
  const std::string_view version_line = trim(in.raw_line("the version line"));
  if (!version_line.starts_with("# vtk DataFile Version"))
    in.fail("not a legacy VTK file (no '# vtk DataFile Version' line)");
  const std::optional<double> version =
      parse_header_number<double>(version_line.substr(std::strlen("# vtk DataFile Version")));
  if (!version || *version < 1.0 || *version >= 6.0)
    in.fail(fmt::format("'{}' is not a version intermix reads (1.0 to 5.1)", shown(version_line)));
  const bool version5 = *version >= 5.0;
  PolyDataFile out;
  out.space = find_space_tag(in.raw_line("the title line"));
  const std::optional<std::string_view> mode = in.line();
  if (mode == "BINARY")
    in.binary = true;
  else if (mode != "ASCII")
    in.fail(fmt::format("line 3 '{}' is not ASCII or BINARY", shown(mode.value_or(""))));
  const std::optional<std::string_view> dataset = in.line();
  const auto dw = dataset ? split_words(*dataset) : std::vector<std::string_view>{};
  if (dw.size() != 2 || dw[0] != "DATASET")
    in.fail(fmt::format("expected 'DATASET POLYDATA', got '{}'", shown(dataset.value_or(""))));
  if (dw[1] != "POLYDATA")
    in.fail(fmt::format("a {} dataset: intermix reads POLYDATA meshes", shown(dw[1])));

  uint64_t points = 0;
  bool has_points = false;
  // With keep_lines: the cells around the lines (VTK orders cell data vertices, lines,
  // polygons, strips) and the CELL_DATA arrays.
  uint64_t vertex_cells = 0, other_cells = 0;
  std::vector<MeshPointData> cell_arrays;
  std::optional<std::string_view> line = in.line();
  while (line) {
    const auto w = split_words(*line);
    const std::string_view key = w[0];
    if (key == "POINTS") {
      const std::vector<uint64_t> c = counts(in, w, 1, *line);
      if (w.size() != 3) in.fail(fmt::format("'{}' is not 'POINTS n type'", shown(*line)));
      points = c[0];
      has_points = true;
      const std::vector<double> xyz = in.values(w[2], points * 3, "POINTS");
      check_memory(points * 12 * 4, file.string());
      out.mesh.positions.resize(static_cast<size_t>(points));
      for (size_t i = 0; i < out.mesh.positions.size(); ++i)
        out.mesh.positions[i] = glm::vec3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    } else if (key == "POLYGONS" || key == "TRIANGLE_STRIPS" || key == "VERTICES" ||
               key == "LINES") {
      if (!has_points) in.fail(fmt::format("{} comes before POINTS", key));
      const auto cells = read_cells(in, *line, version5);
      if (keep_lines && key == "VERTICES") vertex_cells += cells.size();
      if (keep_lines && (key == "POLYGONS" || key == "TRIANGLE_STRIPS"))
        other_cells += cells.size();
      for (size_t c = 0; keep_lines && key == "LINES" && c < cells.size(); ++c) {
        out.lines.indices.insert(out.lines.indices.end(), cells[c].begin(), cells[c].end());
        out.lines.offsets.push_back(out.lines.indices.size());
      }
      for (size_t c = 0; !keep_lines && c < cells.size(); ++c) {
        const std::string what = fmt::format("{}: {} cell {}", file.string(), key, c);
        if (key == "POLYGONS") add_polygon(out.mesh, cells[c], points, what);
        if (key == "TRIANGLE_STRIPS") add_strip(out.mesh, cells[c], points, what);
      }
    } else if (key == "POINT_DATA" || key == "CELL_DATA") {
      const std::vector<uint64_t> c = counts(in, w, 1, *line);
      const bool point_data = key == "POINT_DATA";
      if (point_data && c[0] != points)
        in.fail(fmt::format("POINT_DATA has {} values, but there are {} points", c[0], points));
      line = read_attributes(in, c[0], point_data || keep_lines, out,
                             point_data || !keep_lines ? nullptr : &cell_arrays);
      continue;
    } else if (key == "FIELD" || key == "METADATA") {
      // The dataset's own field data: its SPACE (3D Slicer's), then the next section.
      PolyDataFile field;
      field.space = out.space;
      in.unread(*line);
      line = read_attributes(in, 0, false, field);
      out.space = field.space;
      continue;
    } else {
      in.fail(fmt::format("'{}' is not a polydata section intermix reads", shown(*line)));
    }
    line = in.line();
  }
  if (!has_points) in.fail("the file has no POINTS");
  const uint64_t lines = out.lines.offsets.size() - 1;
  for (const MeshPointData& a : cell_arrays) {
    const uint64_t cells = vertex_cells + lines + other_cells;
    const auto k = static_cast<uint64_t>(a.components);
    if (a.values.size() != cells * k)
      in.fail(fmt::format("CELL_DATA array '{}' holds {} tuples, but the file has {} cells",
                          shown(a.name), a.values.size() / k, cells));
    out.line_data.push_back(
        {a.name, a.components,
         std::vector<double>(
             a.values.begin() + static_cast<ptrdiff_t>(vertex_cells * k),
             a.values.begin() + static_cast<ptrdiff_t>((vertex_cells + lines) * k))});
  }
  if (!out.mesh.normals.empty() && out.mesh.normals.size() != out.mesh.positions.size())
    out.mesh.normals.clear();
  return out;
}

}  // namespace imx::detail
