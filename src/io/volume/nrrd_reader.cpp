#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/input_file.hpp"
#include "io/volume/nrrd.hpp"
#include "io/volume/nrrd_data.hpp"
#include "io/volume/nrrd_dwmri.hpp"
#include "io/voxels/frames.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace {

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
  std::map<std::string, std::string> keys;    // "key:=value" pairs, as written
  std::vector<std::string> list_files;        // the names after 'data file: LIST'
  std::streamoff data_offset = 0;             // where attached data begins
};

// teem's spellings of field names without their blanks, and its older names.
std::string canonical_field(std::string name) {
  static const std::map<std::string, std::string> aliases = {
      {"datafile", "data file"},
      {"centerings", "centers"},
      {"axismins", "axis mins"},
      {"axismaxs", "axis maxs"},
      {"lineskip", "line skip"},
      {"byteskip", "byte skip"},
      {"spacedirections", "space directions"},
      {"spaceorigin", "space origin"},
      {"spacedimension", "space dimension"},
      {"spaceunits", "space units"},
      {"measurementframe", "measurement frame"},
      {"oldmin", "old min"},
      {"oldmax", "old max"},
      {"sampleunits", "sample units"}};
  auto it = aliases.find(name);
  return it == aliases.end() ? name : it->second;
}

Header read_header(std::istream& in, const std::string& what) {
  std::string line;
  if (!read_line(in, line, what) || line.size() < 8 || line.compare(0, 7, "NRRD000") != 0 ||
      !std::isdigit(static_cast<unsigned char>(line[7])))
    throw Error(fmt::format("{}: not a NRRD file (the first line must be NRRD000N)", what));
  Header h;
  size_t total = line.size();
  bool list = false;  // reading the file names after 'data file: LIST'
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
    if (list) {
      // "data file: LIST" puts one file name a line on the rest of the header.
      h.list_files.emplace_back(trim(l));
      continue;
    }
    if (l.front() == '#') continue;
    size_t colon = l.find(':');
    if (colon == std::string_view::npos)
      throw Error(fmt::format("{}: header line '{}' is not 'field: value'", what, shown(l)));
    if (colon + 1 < l.size() && l[colon + 1] == '=') {  // key:=value pairs: metadata
      h.keys[std::string(trim(l.substr(0, colon)))] = std::string(trim(l.substr(colon + 2)));
      continue;
    }
    std::string name = canonical_field(lower(trim(l.substr(0, colon))));
    if (!h.fields.emplace(name, std::string(trim(l.substr(colon + 1)))).second)
      throw Error(fmt::format("{}: field '{}' appears twice", what, name));
    if (name == "data file") {
      const auto words = split_words(l.substr(colon + 1));
      list = !words.empty() && words[0] == "LIST";  // not a file named "LISTS.raw"
    }
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
      std::optional<double> v = parse_header_number<double>(piece);
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
    if (const std::string* sd = find(h, "space dimension");
        sd && parse_header_number<long long>(*sd) != 3)
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

long long parse_count_field(const Header& h, const std::string& name, long long fallback,
                            long long min, const std::string& what) {
  const std::string* v = find(h, name);
  if (!v) return fallback;
  std::optional<long long> n = parse_header_number<long long>(*v);
  if (!n || *n < min)
    throw Error(fmt::format("{}: field '{}' value '{}' must be an integer >= {}", what, name,
                            shown(*v), min));
  return *n;
}

// The most frames (the non-spatial axis of a 4-D file) a header may declare: each gets a label.
constexpr long long kMaxFrames = 1 << 16;
// The most data files a 'data file' list or pattern may name.
constexpr long long kMaxDataFiles = 1 << 16;

// The axes of the file: its sizes, and for a 4-D file which axis holds the frames.
struct Axes {
  int dimension = 3;
  std::vector<long long> sizes;
  int frame_axis = -1;                  // the non-spatial axis of a 4-D file, else -1
  std::array<int, 3> spatial{0, 1, 2};  // the file axes that are i, j, k

  size_t at(int c) const { return static_cast<size_t>(spatial[static_cast<size_t>(c)]); }
};

// A per-axis field's blank-separated entries, one per axis, or nothing when it is absent.
std::optional<std::vector<std::string_view>> axis_words(const Header& h, const std::string& field,
                                                        int dimension, const std::string& what) {
  const std::string* v = find(h, field);
  if (!v) return std::nullopt;
  auto words = split_words(*v);
  if (words.size() != static_cast<size_t>(dimension))
    throw Error(fmt::format("{}: field '{}' has {} entries, expected {}", what, field, words.size(),
                            dimension));
  return words;
}

// A per-axis field of numbers ('spacings', 'axis mins', 'axis maxs'); nan (teem's "unknown")
// and an absent field give NaN.
std::vector<double> axis_numbers(const Header& h, const std::string& field, int dimension,
                                 const std::string& what) {
  std::vector<double> out(static_cast<size_t>(dimension), std::nan(""));
  auto words = axis_words(h, field, dimension, what);
  if (!words) return out;
  for (size_t a = 0; a < words->size(); ++a) {
    std::optional<double> v = parse_header_number<double>((*words)[a]);
    if (!v)
      throw Error(fmt::format("{}: field '{}' value '{}' is not a number", what, field,
                              shown((*words)[a])));
    if (std::isinf(*v))
      throw Error(
          fmt::format("{}: field '{}' value '{}' is not finite", what, field, shown((*words)[a])));
    out[a] = *v;
  }
  return out;
}

bool is_spatial_kind(const std::string& k) {
  return k == "domain" || k == "space";
}
bool is_unknown_kind(const std::string& k) {
  return k == "???" || k == "none";
}

// teem's kinds (nrrdKind), lower case.
bool is_nrrd_kind(const std::string& k) {
  static const char* const kinds[] = {"domain",
                                      "space",
                                      "time",
                                      "list",
                                      "point",
                                      "vector",
                                      "covariant-vector",
                                      "normal",
                                      "stub",
                                      "scalar",
                                      "complex",
                                      "2-vector",
                                      "3-color",
                                      "rgb-color",
                                      "hsv-color",
                                      "xyz-color",
                                      "4-color",
                                      "rgba-color",
                                      "3-vector",
                                      "3-gradient",
                                      "3-normal",
                                      "4-vector",
                                      "quaternion",
                                      "2d-symmetric-matrix",
                                      "2d-masked-symmetric-matrix",
                                      "2d-matrix",
                                      "2d-masked-matrix",
                                      "3d-symmetric-matrix",
                                      "3d-masked-symmetric-matrix",
                                      "3d-matrix",
                                      "3d-masked-matrix",
                                      "???",
                                      "none"};
  return std::find(std::begin(kinds), std::end(kinds), k) != std::end(kinds);
}

void check_kinds_3d(const Header& h, const std::string& what) {
  auto words = axis_words(h, "kinds", 3, what);
  if (!words) return;
  for (size_t a = 0; a < 3; ++a) {
    std::string k = lower((*words)[a]);
    if (!is_spatial_kind(k) && k != "time" && !is_unknown_kind(k))
      throw Error(
          fmt::format("{}: field 'kinds' says axis {} is '{}'; only scalar 3D volumes "
                      "(kinds domain/space) are supported",
                      what, a, (*words)[a]));
  }
}

// Which axis of a 4-D file holds the frames: the one whose 'space directions' entry is 'none';
// else the one 'kinds' calls non-spatial (time, list, vector, a colour, ...), or the one not
// called 'space' when the other three are. Two non-spatial axes, or none to be told, are
// refused: guessing would read frames as slices.
int find_frame_axis(const Header& h, const std::string& what) {
  std::optional<std::vector<std::string>> kinds;
  if (auto words = axis_words(h, "kinds", 4, what)) {
    kinds.emplace();
    for (size_t a = 0; a < 4; ++a) {
      kinds->push_back(lower((*words)[a]));
      if (!is_nrrd_kind(kinds->back()))
        throw Error(fmt::format("{}: field 'kinds' value '{}' (axis {}) is not a NRRD kind", what,
                                shown((*words)[a]), a));
    }
  }
  if (const std::string* dirs = find(h, "space directions")) {
    auto v = parse_vectors(*dirs, "space directions", what);
    if (v.size() != 4)
      throw Error(
          fmt::format("{}: field 'space directions' has {} entries, expected 4", what, v.size()));
    std::vector<int> none;
    for (int a = 0; a < 4; ++a)
      if (!v[static_cast<size_t>(a)]) none.push_back(a);
    if (none.size() != 1)
      throw Error(fmt::format(
          "{}: field 'space directions' has {} 'none' entries; a 4-D volume needs exactly one, "
          "for its axis of frames (three spatial axes and one non-spatial)",
          what, none.size()));
    if (kinds)
      for (int a = 0; a < 4; ++a) {
        const std::string& k = (*kinds)[static_cast<size_t>(a)];
        if (a != none[0] && !is_spatial_kind(k) && k != "time" && !is_unknown_kind(k))
          throw Error(
              fmt::format("{}: field 'kinds' says axis {} is '{}', but 'space "
                          "directions' gives it a direction",
                          what, a, k));
      }
    return none[0];
  }
  if (kinds) {
    std::vector<int> frames, space;
    for (int a = 0; a < 4; ++a) {
      const std::string& k = (*kinds)[static_cast<size_t>(a)];
      if (!is_spatial_kind(k) && !is_unknown_kind(k)) frames.push_back(a);
      if (k == "space") space.push_back(a);
    }
    if (frames.size() > 1)
      throw Error(
          fmt::format("{}: field 'kinds' ('{}') gives {} non-spatial axes; a 4-D volume "
                      "needs three spatial axes and one axis of frames",
                      what, *find(h, "kinds"), frames.size()));
    if (frames.size() == 1) return frames[0];
    if (space.size() == 3)
      for (int a = 0; a < 4; ++a)
        if (std::find(space.begin(), space.end(), a) == space.end()) return a;
  }
  throw Error(fmt::format(
      "{}: a 4-D NRRD, but neither 'space directions' (with 'none' for one axis) nor 'kinds' "
      "(e.g. 'domain domain domain list') says which axis holds the frames",
      what));
}

Axes parse_axes(const Header& h, const std::string& what) {
  Axes ax;
  const std::string& dimension = require(h, "dimension", what);
  const std::optional<long long> d = parse_header_number<long long>(dimension);
  if (d != 3 && d != 4)
    throw Error(
        fmt::format("{}: field 'dimension' is '{}', only 3D volumes and 4-D files of 3D "
                    "frames are supported",
                    what, shown(dimension)));
  ax.dimension = static_cast<int>(*d);

  const std::string& sizes = require(h, "sizes", what);
  auto size_words = split_words(sizes);
  if (size_words.size() != static_cast<size_t>(ax.dimension))
    throw Error(fmt::format("{}: field 'sizes' has {} entries, expected {}", what,
                            size_words.size(), ax.dimension));
  for (auto word : size_words) {
    std::optional<long long> n = parse_header_number<long long>(word);
    if (!n || *n <= 0 || *n > static_cast<long long>(kMaxVoxels))
      throw Error(fmt::format("{}: field 'sizes' value '{}' must be a positive integer", what,
                              shown(word)));
    ax.sizes.push_back(*n);
  }
  if (ax.dimension == 4) {
    ax.frame_axis = find_frame_axis(h, what);
    int c = 0;
    for (int a = 0; a < 4; ++a)
      if (a != ax.frame_axis) ax.spatial[static_cast<size_t>(c++)] = a;
    if (ax.sizes[static_cast<size_t>(ax.frame_axis)] > kMaxFrames)
      throw Error(fmt::format(
          "{}: field 'sizes' gives axis {} (the frames) {} entries; at most "
          "{} frames are supported",
          what, ax.frame_axis, ax.sizes[static_cast<size_t>(ax.frame_axis)], kMaxFrames));
  } else {
    check_kinds_3d(h, what);
  }
  // In double: three sizes up to 2^31 can overflow a size_t product back into range.
  double count = 1;
  for (int c = 0; c < 3; ++c) count *= static_cast<double>(ax.sizes[ax.at(c)]);
  if (count > static_cast<double>(kMaxGridVoxels))
    throw Error(fmt::format("{}: field 'sizes' '{}' gives more than {} voxels", what, shown(sizes),
                            kMaxGridVoxels));
  return ax;
}

enum class Center { unknown, node, cell };

std::vector<Center> parse_centers(const Header& h, int dimension, const std::string& what) {
  std::vector<Center> out(static_cast<size_t>(dimension), Center::unknown);
  auto words = axis_words(h, "centers", dimension, what);
  if (!words) return out;
  for (size_t a = 0; a < words->size(); ++a) {
    const std::string c = lower((*words)[a]);
    if (c == "node")
      out[a] = Center::node;
    else if (c == "cell")
      out[a] = Center::cell;
    else if (!is_unknown_kind(c))
      throw Error(fmt::format("{}: field 'centers' value '{}' (axis {}) is not cell, node or ???",
                              what, shown((*words)[a]), a));
  }
  return out;
}

// The index-to-world of the spatial axes, in teem's precedence:
//  1. 'space directions' (with 'space origin', else 0) place the axes. A spatial axis that also
//     has a spacing, an axis min or an axis max (other than nan) is refused, as teem's
//     nrrdCheck refuses it, rather than pick one of two placements.
//  2. Without them, each axis on its own (a diagonal index-to-world):
//     step:   'spacings' when given (not nan; positive); else from 'axis mins' and 'axis maxs'
//             with the axis's 'centers': node (max - min) / (n - 1), cell (max - min) / n,
//             unknown as cell (teem's nrrdDefaultCenter); else 1.
//     origin: the centre of voxel 0: the axis min (plus half a step when cell-centred); else,
//             from the axis max alone, max - (n - 1) steps (node) or max - (n - 1/2) steps
//             (cell); else 0. 'space origin' gives it instead, and is refused beside axis
//             mins or maxs.
//     A spacing, min and max all given must agree (to 1e-6 of the extent), else refused.
//  Then 'space' turns the result into LPS.
// DWMRI gradients are given in the 'measurement frame' (columns: its axes in the file's space);
// FrameLabel::b_vector is along the volume's i, j, k axes, as a .bvec is before its x flip.
void gradients_to_volume_axes(const Header& h, const glm::dmat4& index_to_world,
                              std::vector<FrameLabel>& labels, const std::string& what) {
  glm::dmat3 frame(1.0);
  if (const std::string* mf = find(h, "measurement frame")) {
    const auto v = parse_vectors(*mf, "measurement frame", what);
    if (v.size() != 3 || !v[0] || !v[1] || !v[2])
      throw Error(fmt::format("{}: field 'measurement frame' needs three vectors", what));
    frame = glm::dmat3(*v[0], *v[1], *v[2]);
  }
  const glm::dvec3 signs = space_signs(h, what);
  const glm::dmat3 axes(index_to_world);
  for (FrameLabel& l : labels) {
    if (!l.b_vector || glm::length(*l.b_vector) == 0.0) continue;
    const glm::dvec3 world = signs * (frame * *l.b_vector);  // LPS
    glm::dvec3 ijk;
    for (int a = 0; a < 3; ++a) ijk[a] = glm::dot(world, glm::normalize(axes[a]));
    l.b_vector = glm::length(ijk) > 0.0 ? glm::normalize(ijk) : ijk;
    l.text = describe_frame(l);
  }
}

glm::dmat4 parse_affine(const Header& h, const Axes& ax, const std::string& what) {
  const int dim = ax.dimension;
  const std::vector<double> spacings = axis_numbers(h, "spacings", dim, what);
  const std::vector<double> mins = axis_numbers(h, "axis mins", dim, what);
  const std::vector<double> maxs = axis_numbers(h, "axis maxs", dim, what);
  const std::vector<Center> centers = parse_centers(h, dim, what);
  for (int c = 0; c < 3; ++c) {
    const double s = spacings[ax.at(c)];
    if (!std::isnan(s) && s <= 0.0)
      throw Error(fmt::format("{}: field 'spacings' value '{}' must be positive", what, s));
  }
  glm::dmat4 m(1.0);
  const std::string* origin = find(h, "space origin");
  if (const std::string* dirs = find(h, "space directions")) {
    auto v = parse_vectors(*dirs, "space directions", what);
    if (v.size() != static_cast<size_t>(dim))
      throw Error(fmt::format("{}: field 'space directions' has {} entries, expected {}", what,
                              v.size(), dim));
    for (int c = 0; c < 3; ++c) {
      const size_t a = ax.at(c);
      if (!v[a])
        throw Error(
            fmt::format("{}: field 'space directions' has 'none' for axis {}; only "
                        "spatial 3D volumes are supported",
                        what, a));
      m[c] = glm::dvec4(*v[a], 0.0);
      const std::pair<const char*, const std::vector<double>*> placed[] = {
          {"spacings", &spacings}, {"axis mins", &mins}, {"axis maxs", &maxs}};
      for (const auto& [field, values] : placed)
        if (!std::isnan((*values)[a]))
          throw Error(fmt::format(
              "{}: field '{}' gives axis {} a value, but 'space directions' already places it "
              "(teem refuses both too; leave '{}' out or make it nan)",
              what, field, a, field));
    }
  } else {
    for (int c = 0; c < 3; ++c) {
      const size_t a = ax.at(c);
      const double n = static_cast<double>(ax.sizes[a]);
      const double lo = mins[a], hi = maxs[a], given = spacings[a];
      const bool node = centers[a] == Center::node;
      double step = 1.0;
      if (!std::isnan(given)) {
        step = given;
        if (!std::isnan(lo) && !std::isnan(hi)) {
          const double extent = (node ? n - 1.0 : n) * given;
          if (std::abs((hi - lo) - extent) > 1e-6 * std::max(std::abs(extent), std::abs(hi - lo)))
            throw Error(fmt::format(
                "{}: fields 'spacings', 'axis mins' and 'axis maxs' disagree on axis {}: {} {}-"
                "centred samples {} apart span {}, not {} to {}",
                what, a, ax.sizes[a], node ? "node" : "cell", given, extent, lo, hi));
        }
      } else if (!std::isnan(lo) && !std::isnan(hi)) {
        step = node ? (ax.sizes[a] > 1 ? (hi - lo) / (n - 1.0) : 1.0) : (hi - lo) / n;
        if (step == 0.0)
          throw Error(
              fmt::format("{}: fields 'axis mins' and 'axis maxs' are both {} for axis "
                          "{}, which has {} samples",
                          what, lo, a, ax.sizes[a]));
      }
      double at = 0.0;
      if (!std::isnan(lo))
        at = lo + (node ? 0.0 : step / 2);
      else if (!std::isnan(hi))
        at = hi - (node ? n - 1.0 : n - 0.5) * step;
      m[c][c] = step;
      m[3][c] = at;
      if (origin && (!std::isnan(lo) || !std::isnan(hi)))
        throw Error(
            fmt::format("{}: fields 'space origin' and 'axis mins'/'axis maxs' both place "
                        "axis {}; give one of them",
                        what, a));
    }
  }
  if (origin) {
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

NrrdEncoding parse_encoding(const Header& h, const std::string& what) {
  const std::string& value = require(h, "encoding", what);
  const std::string e = lower(value);
  if (e == "raw") return NrrdEncoding::raw;
  if (e == "gzip" || e == "gz") return NrrdEncoding::gzip;
  if (e == "bzip2" || e == "bz2") return NrrdEncoding::bzip2;
  if (e == "ascii" || e == "text" || e == "txt") return NrrdEncoding::ascii;
  if (e == "hex") return NrrdEncoding::hex;
  throw Error(
      fmt::format("{}: field 'encoding' has unsupported value '{}' (supported: raw, gzip, "
                  "bzip2, ascii, hex)",
                  what, shown(value)));
}

// "%03d" and the like in a 'data file' pattern, for one number: flags '0', '-', '+', ' ', a
// width, a precision, and d, i or u. Anything else ("%s", two numbers) is refused: the
// pattern comes from the file and goes to no printf.
std::string format_file_name(const std::string& pattern, long long number,
                             const std::string& what) {
  std::string out;
  int conversions = 0;
  auto fail = [&](const std::string& why) {
    return Error(fmt::format("{}: field 'data file' pattern '{}' {}", what, shown(pattern), why));
  };
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') {
      out.push_back(pattern[i]);
      continue;
    }
    if (++i < pattern.size() && pattern[i] == '%') {
      out.push_back('%');
      continue;
    }
    bool zero = false, left = false, plus = false, space = false;
    for (; i < pattern.size() && std::strchr("0-+ ", pattern[i]); ++i) {
      zero |= pattern[i] == '0';
      left |= pattern[i] == '-';
      plus |= pattern[i] == '+';
      space |= pattern[i] == ' ';
    }
    size_t width = 0, precision = 0;
    bool has_precision = false;
    for (; i < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[i])); ++i)
      width = std::min<size_t>(width * 10 + static_cast<size_t>(pattern[i] - '0'), 256);
    if (i < pattern.size() && pattern[i] == '.') {
      has_precision = true;
      for (++i; i < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[i])); ++i)
        precision = std::min<size_t>(precision * 10 + static_cast<size_t>(pattern[i] - '0'), 256);
    }
    if (i >= pattern.size() || !std::strchr("diu", pattern[i]))
      throw fail("has a conversion other than %d, %i or %u");
    if (++conversions > 1) throw fail("has more than one number conversion");
    if (pattern[i] == 'u' && number < 0)
      throw fail(fmt::format("gives %u the negative {}", number));
    std::string digits = std::to_string(number < 0 ? -number : number);
    if (has_precision && digits.size() < precision)
      digits.insert(0, precision - digits.size(), '0');
    const std::string sign = number < 0 ? "-" : plus ? "+" : space ? " " : "";
    std::string body = sign + digits;
    if (body.size() < width) {
      const size_t pad = width - body.size();
      if (left)
        body.append(pad, ' ');
      else if (zero && !has_precision)
        body = sign + std::string(pad, '0') + digits;
      else
        body.insert(0, pad, ' ');
    }
    out += body;
  }
  if (conversions != 1) throw fail("has no %d conversion");
  return out;
}

// The data files a 'data file' field names: one file, "LIST [subdim]" with the names on the
// following lines, or "pattern min max step [subdim]" (teem's forms). Each file holds an equal
// share of the data: with subdim < dimension (the default: dimension - 1) one file per
// subdim-dimensional piece, so as many files as the slower axes' sizes multiply to; with
// subdim = dimension any count that divides the elements.
std::vector<std::string> parse_data_files(const Header& h, const Axes& ax, uint64_t elements,
                                          const std::string& what) {
  const std::string* value = find(h, "data file");
  if (!value) return {};
  auto words = split_words(*value);
  std::vector<std::string> names;
  std::optional<std::string_view> subdim_word;
  if (!words.empty() && words[0] == "LIST") {
    if (words.size() > 2)
      throw Error(fmt::format("{}: field 'data file' value '{}' is not 'LIST [subdim]'", what,
                              shown(*value)));
    if (words.size() == 2) subdim_word = words[1];
    names = h.list_files;
    if (names.empty())
      throw Error(fmt::format("{}: field 'data file' is LIST but no file names follow it", what));
    if (names.size() > static_cast<size_t>(kMaxDataFiles))
      throw Error(
          fmt::format("{}: field 'data file' lists more than {} files", what, kMaxDataFiles));
  } else if ((words.size() == 4 || words.size() == 5) &&
             words[0].find('%') != std::string_view::npos) {
    std::optional<long long> lo = parse_header_number<long long>(words[1]),
                             hi = parse_header_number<long long>(words[2]),
                             step = parse_header_number<long long>(words[3]);
    if (!lo || !hi || !step || *step == 0 || (*step > 0 ? *lo > *hi : *lo < *hi) ||
        std::abs(*lo) > (1LL << 40) || std::abs(*hi) > (1LL << 40))
      throw Error(
          fmt::format("{}: field 'data file' value '{}' is not 'pattern min max step "
                      "[subdim]' with a step that goes from min to max",
                      what, shown(*value)));
    if (words.size() == 5) subdim_word = words[4];
    const long long count = (*hi - *lo) / *step + 1;
    if (count > kMaxDataFiles)
      throw Error(fmt::format("{}: field 'data file' names {} files, more than {}", what, count,
                              kMaxDataFiles));
    for (long long i = 0; i < count; ++i)
      names.push_back(format_file_name(std::string(words[0]), *lo + i * *step, what));
  } else {
    return {*value};
  }

  long long subdim = ax.dimension - 1;
  if (subdim_word) {
    std::optional<long long> s = parse_header_number<long long>(*subdim_word);
    if (!s || *s < 1 || *s > ax.dimension)
      throw Error(fmt::format("{}: field 'data file' subdim '{}' must be from 1 to {}", what,
                              shown(*subdim_word), ax.dimension));
    subdim = *s;
  }
  if (subdim < ax.dimension) {
    uint64_t pieces = 1;
    for (long long a = subdim; a < ax.dimension; ++a)
      pieces *= static_cast<uint64_t>(ax.sizes[static_cast<size_t>(a)]);
    if (pieces != names.size())
      throw Error(
          fmt::format("{}: field 'data file' names {} files, but 'sizes' '{}' has {} "
                      "pieces of {} dimensions, one a file",
                      what, names.size(), *find(h, "sizes"), pieces, subdim));
  } else if (elements % names.size() != 0) {
    throw Error(
        fmt::format("{}: field 'data file' names {} files, which cannot share the {} "
                    "elements equally",
                    what, names.size(), elements));
  }
  return names;
}

// What the header says about the volume and where its voxels are.
struct Layout {
  VolumeHeader header;
  NrrdData data;
  NrrdGrid grid;
};

// Reads and checks the header at the start of `in`.
Layout parse_layout(std::istream& in, const std::filesystem::path& file) {
  const std::string what = file.string();
  const Header h = read_header(in, what);
  Layout l;
  const Axes ax = parse_axes(h, what);
  l.data.header = file;
  l.data.type = parse_type(require(h, "type", what), what);
  l.header.type = storage_type_for(l.data.type);
  for (int c = 0; c < 3; ++c) l.header.dims[c] = static_cast<int>(ax.sizes[ax.at(c)]);

  // Strides of the file's axes in elements, the first fastest.
  std::array<uint64_t, 4> strides{1, 1, 1, 1};
  for (int a = 1; a < ax.dimension; ++a)
    strides[static_cast<size_t>(a)] = strides[static_cast<size_t>(a - 1)] *
                                      static_cast<uint64_t>(ax.sizes[static_cast<size_t>(a - 1)]);
  l.data.elements =
      strides[static_cast<size_t>(ax.dimension - 1)] * static_cast<uint64_t>(ax.sizes.back());
  l.grid.dims = l.header.dims;
  for (int c = 0; c < 3; ++c) l.grid.stride[static_cast<size_t>(c)] = strides[ax.at(c)];
  if (ax.frame_axis >= 0) {
    l.grid.frames = static_cast<int>(ax.sizes[static_cast<size_t>(ax.frame_axis)]);
    l.grid.frame_stride = strides[static_cast<size_t>(ax.frame_axis)];
  }
  l.header.frames = l.grid.frames;
  if (ax.frame_axis >= 0) l.header.frame_labels = dwmri_frame_labels(h.keys, l.grid.frames, what);
  l.data.shape = fmt::format("{}", fmt::join(ax.sizes, "x"));

  l.data.encoding = parse_encoding(h, what);
  // Byte order matters wherever the bytes of elements are stored: all but ascii.
  if (const std::string* endian = find(h, "endian")) {
    std::string e = lower(*endian);
    if (e != "little" && e != "big")
      throw Error(fmt::format("{}: field 'endian' has value '{}' (expected little or big)", what,
                              shown(*endian)));
    l.data.big_endian = e == "big";
  } else if (raw_type_size(l.data.type) > 1 && l.data.encoding != NrrdEncoding::ascii) {
    throw Error(fmt::format("{}: missing field 'endian' (needed for type '{}')", what,
                            require(h, "type", what)));
  }

  l.header.index_to_world = parse_affine(h, ax, what);
  if (!l.header.frame_labels.empty())
    gradients_to_volume_axes(h, l.header.index_to_world, l.header.frame_labels, what);

  l.data.line_skip = parse_count_field(h, "line skip", 0, 0, what);
  if (find(h, "byte skip")) l.data.byte_skip = parse_count_field(h, "byte skip", 0, -1, what);
  if (l.data.byte_skip == -1 && l.data.encoding != NrrdEncoding::raw)
    throw Error(fmt::format("{}: field 'byte skip' -1 is only allowed with raw encoding", what));

  l.data.files = parse_data_files(h, ax, l.data.elements, what);
  if (l.data.files.empty()) {
    if (h.data_offset < 0)
      throw Error(
          fmt::format("{}: the header ends without a blank line and there is no 'data file' "
                      "field, so there is no voxel data",
                      what));
    l.data.attached_offset = static_cast<uint64_t>(h.data_offset);
  }
  return l;
}

std::ifstream open_header(const std::filesystem::path& file) {
  std::ifstream in = open_input_stream(file, file.string());
  return in;
}

Layout read_layout(const std::filesystem::path& file) {
  std::ifstream in = open_header(file);
  return parse_layout(in, file);
}

}  // namespace

VolumeHeader read_nrrd_header(const std::filesystem::path& file) {
  VolumeHeader header = read_layout(file).header;
  check_placement(header.index_to_world, file.string());
  return header;
}

VolumeData read_nrrd_region(const std::filesystem::path& file, const VoxelBox& box, int frame) {
  const std::string what = file.string();
  const Layout layout = read_layout(file);
  require_frame(frame, layout.grid.frames, what);
  require_box_inside(layout.header.dims, box, what);
  VolumeData v;
  v.dims = box.size();
  v.index_to_world = box_index_to_world(layout.header.index_to_world, box.lo);
  v.voxels = read_nrrd_voxels(layout.data, layout.grid, frame, box);
  v.validate(what);
  return v;
}

VolumeData read_nrrd(const std::filesystem::path& file, int frame) {
  const std::string what = file.string();
  const Layout layout = read_layout(file);
  require_frame(frame, layout.grid.frames, what);
  VolumeData v;
  v.dims = layout.header.dims;
  v.index_to_world = layout.header.index_to_world;
  v.voxels = read_nrrd_voxels(layout.data, layout.grid, frame, VoxelBox::whole(v.dims));
  v.validate(what);
  return v;
}

}  // namespace imx::detail
