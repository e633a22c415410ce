#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/frames.hpp"
#include "io/gzip.hpp"
#include "io/header_text.hpp"
#include "io/nrrd.hpp"
#include "io/raw_voxels.hpp"
#include "io/regular_file.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace {

std::optional<double> parse_double(std::string_view s) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

std::optional<long long> parse_integer(std::string_view s) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  long long v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

// Reads one line without its end-of-line; false at end of file. Throws on an endless line.
bool read_line(std::istream& in, std::string& line, const std::string& what) {
  line.clear();
  int c;
  while ((c = in.get()) != std::char_traits<char>::eof()) {
    if (c == '\n') return true;
    if (line.size() >= kMaxHeaderLineBytes)
      throw Error(fmt::format("{}: header line longer than {} bytes (not a NRRD header?)", what,
                              kMaxHeaderLineBytes));
    line.push_back(static_cast<char>(c));
  }
  return !line.empty();
}

struct Header {
  std::map<std::string, std::string> fields;  // field name (lower case) -> trimmed value
  std::streamoff data_offset = 0;             // where attached data begins
};

Header read_header(std::istream& in, const std::string& what) {
  std::string line;
  if (!read_line(in, line, what) || line.size() < 8 || line.compare(0, 7, "NRRD000") != 0 ||
      !std::isdigit(static_cast<unsigned char>(line[7])))
    throw Error(fmt::format("{}: not a NRRD file (the first line must be NRRD000N)", what));
  Header h;
  size_t total = line.size();
  while (read_line(in, line, what)) {
    total += line.size() + 1;
    if (total > kMaxHeaderBytes)
      throw Error(
          fmt::format("{}: header longer than {} bytes (missing the blank line that ends "
                      "it?)",
                      what, kMaxHeaderBytes));
    std::string_view l = line;
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    if (l.empty()) break;  // the blank line: attached data follows
    if (l.front() == '#') continue;
    size_t colon = l.find(':');
    if (colon == std::string_view::npos)
      throw Error(fmt::format("{}: header line '{}' is not 'field: value'", what, shown(l)));
    if (colon + 1 < l.size() && l[colon + 1] == '=') continue;  // key:=value pairs: metadata
    std::string name = lower(trim(l.substr(0, colon)));
    if (name == "datafile") name = "data file";
    if (name == "centerings") name = "centers";
    if (!h.fields.emplace(name, std::string(trim(l.substr(colon + 1)))).second)
      throw Error(fmt::format("{}: field '{}' appears twice", what, name));
    // "data file: LIST" puts file names on the following lines: not header fields.
    if (name == "data file" && trim(l.substr(colon + 1)).substr(0, 4) == "LIST") break;
  }
  h.data_offset = in.tellg();
  return h;
}

const std::string* find(const Header& h, const std::string& name) {
  auto it = h.fields.find(name);
  return it == h.fields.end() ? nullptr : &it->second;
}

const std::string& require(const Header& h, const std::string& name, const std::string& what) {
  if (const std::string* v = find(h, name)) return *v;
  throw Error(fmt::format("{}: missing field '{}'", what, name));
}

RawType parse_type(const std::string& value, const std::string& what) {
  static const std::map<std::string, RawType> names = {{"signed char", RawType::i8},
                                                       {"int8", RawType::i8},
                                                       {"int8_t", RawType::i8},
                                                       {"uchar", RawType::u8},
                                                       {"unsigned char", RawType::u8},
                                                       {"uint8", RawType::u8},
                                                       {"uint8_t", RawType::u8},
                                                       {"short", RawType::i16},
                                                       {"short int", RawType::i16},
                                                       {"signed short", RawType::i16},
                                                       {"signed short int", RawType::i16},
                                                       {"int16", RawType::i16},
                                                       {"int16_t", RawType::i16},
                                                       {"ushort", RawType::u16},
                                                       {"unsigned short", RawType::u16},
                                                       {"unsigned short int", RawType::u16},
                                                       {"uint16", RawType::u16},
                                                       {"uint16_t", RawType::u16},
                                                       {"int", RawType::i32},
                                                       {"signed int", RawType::i32},
                                                       {"int32", RawType::i32},
                                                       {"int32_t", RawType::i32},
                                                       {"uint", RawType::u32},
                                                       {"unsigned int", RawType::u32},
                                                       {"uint32", RawType::u32},
                                                       {"uint32_t", RawType::u32},
                                                       {"longlong", RawType::i64},
                                                       {"long long", RawType::i64},
                                                       {"long long int", RawType::i64},
                                                       {"signed long long", RawType::i64},
                                                       {"signed long long int", RawType::i64},
                                                       {"int64", RawType::i64},
                                                       {"int64_t", RawType::i64},
                                                       {"ulonglong", RawType::u64},
                                                       {"unsigned long long", RawType::u64},
                                                       {"unsigned long long int", RawType::u64},
                                                       {"uint64", RawType::u64},
                                                       {"uint64_t", RawType::u64},
                                                       {"float", RawType::f32},
                                                       {"double", RawType::f64}};
  auto it = names.find(lower(value));
  if (it == names.end())
    throw Error(
        fmt::format("{}: field 'type' has unsupported value '{}' (supported: integer types "
                    "of 8 to 64 bits, float, double)",
                    what, shown(value)));
  return it->second;
}

// "(x,y,z)" groups or "none", as in 'space directions' and 'space origin'.
std::vector<std::optional<glm::dvec3>> parse_vectors(const std::string& value,
                                                     const std::string& field,
                                                     const std::string& what) {
  std::vector<std::optional<glm::dvec3>> out;
  std::string_view s = value;
  auto fail = [&](const std::string& why) {
    return Error(fmt::format("{}: field '{}' value '{}': {}", what, field, shown(value), why));
  };
  while (true) {
    s = trim(s);
    if (s.empty()) break;
    if (s.substr(0, 4) == "none") {
      out.push_back(std::nullopt);
      s.remove_prefix(4);
      continue;
    }
    if (s.front() != '(') throw fail("expected '(x,y,z)' or 'none'");
    size_t close = s.find(')');
    if (close == std::string_view::npos) throw fail("missing ')'");
    std::string_view inner = s.substr(1, close - 1);
    std::vector<double> parts;
    size_t start = 0;
    while (true) {
      size_t comma = inner.find(',', start);
      std::string_view piece = inner.substr(
          start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
      std::optional<double> v = parse_double(piece);
      if (!v) throw fail(fmt::format("'{}' is not a number", trim(piece)));
      if (!std::isfinite(*v)) throw fail("non-finite value (NaN or infinity)");
      parts.push_back(*v);
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (parts.size() != 3)
      throw fail(fmt::format("vectors need 3 components, found {}", parts.size()));
    out.push_back(glm::dvec3(parts[0], parts[1], parts[2]));
    s.remove_prefix(close + 1);
  }
  return out;
}

// +1/-1 per world axis to turn the file's space into LPS.
glm::dvec3 space_signs(const Header& h, const std::string& what) {
  const std::string* space = find(h, "space");
  if (!space) {
    if (const std::string* sd = find(h, "space dimension"); sd && parse_integer(*sd) != 3)
      throw Error(
          fmt::format("{}: field 'space dimension' is '{}', only 3 is supported", what, *sd));
    return {1, 1, 1};  // no named space: take the coordinates as they are
  }
  std::string s = lower(*space);
  if (s == "left-posterior-superior" || s == "lps" || s == "scanner-xyz" || s == "3d-right-handed")
    return {1, 1, 1};
  if (s == "right-anterior-superior" || s == "ras") return {-1, -1, 1};
  if (s == "left-anterior-superior" || s == "las") return {1, -1, 1};
  throw Error(
      fmt::format("{}: field 'space' has unsupported value '{}' (supported: "
                  "left-posterior-superior, right-anterior-superior, "
                  "left-anterior-superior)",
                  what, shown(*space)));
}

glm::dmat4 parse_affine(const Header& h, const std::string& what) {
  glm::dmat4 m(1.0);
  if (const std::string* dirs = find(h, "space directions")) {
    auto v = parse_vectors(*dirs, "space directions", what);
    if (v.size() != 3)
      throw Error(
          fmt::format("{}: field 'space directions' has {} entries, expected 3", what, v.size()));
    for (int a = 0; a < 3; ++a) {
      if (!v[a])
        throw Error(
            fmt::format("{}: field 'space directions' has 'none' for axis {}; only "
                        "spatial 3D volumes are supported",
                        what, a));
      m[a] = glm::dvec4(*v[a], 0.0);
    }
  } else if (const std::string* sp = find(h, "spacings")) {
    auto words = split_words(*sp);
    if (words.size() != 3)
      throw Error(
          fmt::format("{}: field 'spacings' has {} entries, expected 3", what, words.size()));
    for (int a = 0; a < 3; ++a) {
      std::optional<double> s = parse_double(words[a]);
      if (!s)
        throw Error(
            fmt::format("{}: field 'spacings' value '{}' is not a number", what, shown(words[a])));
      if (std::isnan(*s)) s = 1.0;  // NRRD writes nan for "unknown": unit spacing
      if (!std::isfinite(*s) || *s <= 0.0)
        throw Error(
            fmt::format("{}: field 'spacings' value '{}' must be positive", what, shown(words[a])));
      m[a][a] = *s;
    }
  }
  if (const std::string* origin = find(h, "space origin")) {
    auto v = parse_vectors(*origin, "space origin", what);
    if (v.size() != 1 || !v[0])
      throw Error(fmt::format("{}: field 'space origin' must be one '(x,y,z)'", what));
    m[3] = glm::dvec4(*v[0], 1.0);
  }
  glm::dvec3 sign = space_signs(h, what);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r) m[c][r] *= sign[r];
  return m;
}

void check_kinds(const Header& h, const std::string& what) {
  const std::string* kinds = find(h, "kinds");
  if (!kinds) return;
  auto words = split_words(*kinds);
  if (words.size() != 3)
    throw Error(fmt::format("{}: field 'kinds' has {} entries, expected 3", what, words.size()));
  for (size_t a = 0; a < 3; ++a) {
    std::string k = lower(words[a]);
    if (k != "domain" && k != "space" && k != "time" && k != "none" && k != "???")
      throw Error(
          fmt::format("{}: field 'kinds' says axis {} is '{}'; only scalar 3D volumes "
                      "(kinds domain/space) are supported",
                      what, a, words[a]));
  }
}

long long parse_count_field(const Header& h, const std::string& name, long long fallback,
                            long long min, const std::string& what) {
  const std::string* v = find(h, name);
  if (!v) return fallback;
  std::optional<long long> n = parse_integer(*v);
  if (!n || *n < min)
    throw Error(fmt::format("{}: field '{}' value '{}' must be an integer >= {}", what, name,
                            shown(*v), min));
  return *n;
}

// What the header says about the volume and where its voxels are.
struct Layout {
  VolumeHeader header;
  RawType type = RawType::u8;
  bool gzipped = false, big_endian = false;
  long long line_skip = 0, byte_skip = 0;
  const std::string* data_file = nullptr;  // a detached data file's name, else attached
  std::streamoff data_offset = 0;          // where attached data begins
};

// Reads and checks the header at the start of `in`; `h` keeps the fields `layout` points into.
Layout parse_layout(std::istream& in, Header& h, const std::string& what) {
  h = read_header(in, what);
  Layout l;
  l.data_offset = h.data_offset;

  const std::string& dimension = require(h, "dimension", what);
  if (parse_integer(dimension) != 3)
    throw Error(fmt::format("{}: field 'dimension' is '{}', only 3D volumes are supported", what,
                            shown(dimension)));
  l.type = parse_type(require(h, "type", what), what);
  l.header.type = storage_type_for(l.type);

  auto size_words = split_words(require(h, "sizes", what));
  if (size_words.size() != 3)
    throw Error(
        fmt::format("{}: field 'sizes' has {} entries, expected 3", what, size_words.size()));
  size_t count = 1;
  for (int a = 0; a < 3; ++a) {
    std::optional<long long> n = parse_integer(size_words[a]);
    if (!n || *n <= 0 || *n > static_cast<long long>(kMaxVoxels))
      throw Error(fmt::format("{}: field 'sizes' value '{}' must be a positive integer", what,
                              shown(size_words[a])));
    l.header.dims[a] = static_cast<int>(*n);
    count *= static_cast<size_t>(*n);
    if (count > kMaxVoxels)
      throw Error(fmt::format("{}: field 'sizes' '{}' gives more than {} voxels", what,
                              shown(require(h, "sizes", what)), kMaxVoxels));
  }
  check_kinds(h, what);

  std::string encoding = lower(require(h, "encoding", what));
  l.gzipped = encoding == "gzip" || encoding == "gz";
  if (!l.gzipped && encoding != "raw")
    throw Error(
        fmt::format("{}: field 'encoding' has unsupported value '{}' (supported: raw, "
                    "gzip)",
                    what, shown(encoding)));

  if (const std::string* endian = find(h, "endian")) {
    std::string e = lower(*endian);
    if (e != "little" && e != "big")
      throw Error(fmt::format("{}: field 'endian' has value '{}' (expected little or big)", what,
                              shown(*endian)));
    l.big_endian = e == "big";
  } else if (raw_type_size(l.type) > 1) {
    throw Error(fmt::format("{}: missing field 'endian' (needed for type '{}')", what,
                            require(h, "type", what)));
  }

  l.header.index_to_world = parse_affine(h, what);

  l.line_skip = parse_count_field(h, "line skip", 0, 0, what);
  l.byte_skip = parse_count_field(h, "byte skip", 0, -1, what);
  if (l.byte_skip < 0 && l.gzipped)
    throw Error(fmt::format("{}: field 'byte skip' -1 is only allowed with raw encoding", what));

  if (const std::string* name = find(h, "data file")) {
    auto words = split_words(*name);
    if (name->substr(0, 4) == "LIST" || (words.size() > 1 && name->find('%') != std::string::npos))
      throw Error(
          fmt::format("{}: field 'data file' lists several files; only one detached data "
                      "file is supported",
                      what));
    l.data_file = name;
  } else if (h.data_offset < 0) {
    throw Error(
        fmt::format("{}: the header ends without a blank line and there is no 'data file' "
                    "field, so there is no voxel data",
                    what));
  }
  return l;
}

// The voxels of `box` from the data `layout` locates: after the header in `in`, or in the
// detached data file named relative to the header.
VoxelStorage read_voxels(const std::filesystem::path& file, std::ifstream& in, const Layout& layout,
                         const VoxelBox& box) {
  const std::string what = file.string();
  const glm::ivec3 dims = layout.header.dims;
  std::filesystem::path data_path = file;
  std::streamoff start = layout.data_offset;
  std::string data_what = what;
  if (layout.data_file) {
    data_path = resolve_data_file(file, *layout.data_file, "field 'data file'");
    data_what = fmt::format("{} (data file of {})", data_path.string(), what);
    in.close();
    in.open(data_path, std::ios::binary);
    if (!in) throw FileError(fmt::format("{}: cannot open the data file", data_what), errno);
    start = 0;
  }
  in.clear();
  in.seekg(start);
  for (long long i = 0; i < layout.line_skip; ++i) {
    int c;
    while ((c = in.get()) != '\n')
      if (c == std::char_traits<char>::eof())
        throw Error(fmt::format("{}: field 'line skip' {} goes past the end of the data", what,
                                layout.line_skip));
  }
  start = in.tellg();

  std::error_code ec;
  uintmax_t file_size = std::filesystem::file_size(data_path, ec);
  if (ec)
    throw Error(fmt::format("{}: cannot read the size of the data: {}", data_what, ec.message()));
  size_t available = file_size > static_cast<uintmax_t>(start) ? file_size - start : 0;
  const size_t needed = static_cast<size_t>(dims.x) * dims.y * dims.z * raw_type_size(layout.type);

  if (!layout.gzipped) {
    size_t offset = static_cast<size_t>(start);
    if (layout.byte_skip < 0) {
      offset = file_size >= needed ? file_size - needed : 0;
      if (offset < static_cast<size_t>(start)) offset = static_cast<size_t>(start);
    } else {
      offset += static_cast<size_t>(layout.byte_skip);
    }
    // The whole grid's data must be there, as for a whole read, even when the box needs less.
    size_t found = file_size > offset ? file_size - offset : 0;
    if (found < needed)
      throw Error(fmt::format("{}: expected {} bytes of voxel data ({}x{}x{} {}), found {}",
                              data_what, needed, dims.x, dims.y, dims.z, raw_type_name(layout.type),
                              found));
    return load_raw_voxels(in, offset, layout.type, dims, box, layout.big_endian, data_what);
  }
  check_inflatable(needed + static_cast<size_t>(layout.byte_skip), available, data_what);
  return load_gzip_voxels(in, static_cast<size_t>(layout.byte_skip), layout.type, dims, box,
                          layout.big_endian, data_what);
}

std::ifstream open_header(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw FileError(fmt::format("{}: cannot open file", file.string()), errno);
  return in;
}

}  // namespace

VolumeHeader read_nrrd_header(const std::filesystem::path& file) {
  const std::string what = file.string();
  std::ifstream in = open_header(file);
  Header h;
  VolumeHeader header = parse_layout(in, h, what).header;
  check_placement(header.index_to_world, what);
  return header;
}

VolumeData read_nrrd_region(const std::filesystem::path& file, const VoxelBox& box,
                                int frame) {
  require_frame(frame, 1, file.string());
  const std::string what = file.string();
  std::ifstream in = open_header(file);
  Header h;
  const Layout layout = parse_layout(in, h, what);
  require_box_inside(layout.header.dims, box, what);
  VolumeData v;
  v.dims = box.size();
  v.index_to_world = box_index_to_world(layout.header.index_to_world, box.lo);
  v.voxels = read_voxels(file, in, layout, box);
  v.validate(what);
  return v;
}

VolumeData read_nrrd(const std::filesystem::path& file, int frame) {
  require_frame(frame, 1, file.string());
  const std::string what = file.string();
  std::ifstream in = open_header(file);
  Header h;
  const Layout layout = parse_layout(in, h, what);
  VolumeData v;
  v.dims = layout.header.dims;
  v.index_to_world = layout.header.index_to_world;
  v.voxels = read_voxels(file, in, layout, VoxelBox::whole(v.dims));
  v.validate(what);
  return v;
}

}  // namespace imx::detail
