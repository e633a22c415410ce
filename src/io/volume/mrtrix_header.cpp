// MRtrix's image formats (https://mrtrix.readthedocs.io, "MRtrix image formats"): the text header
// of "key: value" lines between "mrtrix image" and "END". Checked against mrconvert (MRtrix 3) in
// the tests.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/file_head.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/regular_file.hpp"
#include "io/volume/mrtrix.hpp"
#include "io/volume/mrtrix_header.hpp"
#include "io/voxels/frame_voxels.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kMagic = "mrtrix image";
// Headers hold dims, a transform, a gradient table and a command history: kB, rarely more.
constexpr size_t kFirstHeaderRead = size_t{1} << 20;
constexpr size_t kMaxMrtrixHeader = size_t{16} << 20;
// MRtrix images have at most 16 axes; intermix shows 3, with volumes along the 4th.
constexpr size_t kMaxAxes = 16;

struct Header {
  std::string what;
  std::map<std::string, std::string> keys;  // dim, vox, layout, datatype, scaling (last wins)
  std::vector<std::string> transform;       // each "transform:" line, in order
  std::vector<std::string> files;           // each "file:" line
  size_t end = 0;                           // bytes up to and including the END line

  const std::string& require(const std::string& key) const {
    auto it = keys.find(key);
    if (it == keys.end()) throw Error(fmt::format("{}: missing key '{}'", what, key));
    return it->second;
  }
  Error bad(std::string_view key, std::string_view value, const std::string& why) const {
    return Error(fmt::format("{}: key '{}' value '{}' {}", what, key, shown(value), why));
  }
};

// Parses the header lines as MRtrix's key/value reader does: text after '#' is a comment,
// surrounding blanks (and a DOS '\r') are dropped, lines without ':' are ignored, END ends it.
std::optional<Header> parse_header_text(std::string_view text, const std::string& what) {
  Header h;
  h.what = what;
  const size_t first_end = text.find('\n');
  if (text.substr(0, kMagic.size()) != kMagic)
    throw Error(fmt::format("{}: not an MRtrix image (its first line is not '{}')", what, kMagic));
  if (first_end == std::string_view::npos) return std::nullopt;
  size_t at = first_end + 1;
  while (at < text.size()) {
    const size_t eol = text.find('\n', at);
    if (eol == std::string_view::npos) return std::nullopt;  // END not within the text read
    std::string_view line = text.substr(at, eol - at);
    at = eol + 1;
    line = trim(line.substr(0, line.find('#')));
    if (line == "END") {
      h.end = at;
      return h;
    }
    const size_t colon = line.find(':');
    if (colon == std::string_view::npos) continue;
    const std::string key(trim(line.substr(0, colon)));
    const std::string value(trim(line.substr(colon + 1)));
    if (key.empty()) continue;
    const std::string lkey = lower(key);
    if (lkey == "transform")
      h.transform.push_back(value);
    else if (key == "file")
      h.files.push_back(value);
    else if (lkey == "dim" || lkey == "vox" || lkey == "layout" || lkey == "datatype" ||
             lkey == "scaling")
      h.keys[lkey] = value;
  }
  return std::nullopt;
}

// The comma-separated entries of a value, blanks around each dropped.
std::vector<std::string_view> entries(std::string_view value) {
  std::vector<std::string_view> out;
  size_t at = 0;
  while (true) {
    const size_t comma = value.find(',', at);
    out.push_back(trim(value.substr(at, comma == std::string_view::npos ? comma : comma - at)));
    if (comma == std::string_view::npos || out.size() > kMaxAxes * 4) return out;
    at = comma + 1;
  }
}

std::vector<double> parse_floats(const Header& h, std::string_view key, std::string_view value) {
  std::vector<double> out;
  for (std::string_view e : entries(value)) {
    const std::optional<double> v = parse_header_number<double>(e);
    if (!v) throw h.bad(key, value, fmt::format("holds '{}', which is not a number", shown(e)));
    out.push_back(*v);
  }
  return out;
}

struct DataType {
  RawType type = RawType::u8;
  bool big_endian = false;
};

DataType parse_datatype(const Header& h) {
  const std::string& value = h.require("datatype");
  std::string name = lower(trim(value));
  DataType d;
  if (name.size() > 2 && (name.ends_with("le") || name.ends_with("be"))) {
    d.big_endian = name.ends_with("be");
    name.resize(name.size() - 2);
  }  // no suffix: the native order, little-endian on the machines MRtrix writes for
  static const std::map<std::string, RawType> types = {
      {"int8", RawType::i8},    {"uint8", RawType::u8},   {"int16", RawType::i16},
      {"uint16", RawType::u16}, {"int32", RawType::i32},  {"uint32", RawType::u32},
      {"int64", RawType::i64},  {"uint64", RawType::u64}, {"float32", RawType::f32},
      {"float64", RawType::f64}};
  if (name == "bit")
    throw h.bad("datatype", value, "(1-bit masks packed 8 to a byte) is not supported");
  if (name.starts_with("cfloat"))
    throw h.bad("datatype", value,
                "(complex) is not supported: complex voxels have no value to render");
  auto it = types.find(name);
  if (it == types.end())
    throw h.bad("datatype", value,
                "is not an MRtrix data type (Int8, UInt8, [U]Int16/32/64 and Float32/64, with LE "
                "or BE)");
  d.type = it->second;
  return d;
}

// "+2,-0,-1": per axis, a sign (the direction on file) and a rank (0 varies fastest).
void parse_layout(const Header& h, const std::vector<int64_t>& dims, MrtrixStorage& s) {
  const std::string& value = h.require("layout");
  const std::vector<std::string_view> parts = entries(value);
  if (parts.size() != dims.size())
    throw h.bad("layout", value,
                fmt::format("has {} entries for {} axes (dim)", parts.size(), dims.size()));
  std::vector<int> rank(dims.size(), -1);
  std::vector<bool> taken(dims.size(), false), reversed(dims.size(), false);
  for (size_t a = 0; a < parts.size(); ++a) {
    std::string_view p = parts[a];
    if (!p.empty() && (p.front() == '+' || p.front() == '-')) {
      reversed[a] = p.front() == '-';
      p.remove_prefix(1);
    }
    const std::optional<int> r = p.empty() || !std::isdigit(static_cast<unsigned char>(p.front()))
                                     ? std::nullopt
                                     : parse_header_number<int>(p);
    if (!r || *r < 0 || static_cast<size_t>(*r) >= dims.size())
      throw h.bad("layout", value,
                  fmt::format("has entry '{}'; each must be a sign and an axis rank from 0 to {}",
                              shown(parts[a]), dims.size() - 1));
    if (taken[static_cast<size_t>(*r)])
      throw h.bad("layout", value, fmt::format("gives rank {} twice", *r));
    taken[static_cast<size_t>(*r)] = true;
    rank[a] = *r;
  }
  // Axes beyond the 4th have size 1 (checked by the caller): they change no offset.
  std::vector<int> axes;
  for (size_t a = 0; a < dims.size() && a < 4; ++a) axes.push_back(static_cast<int>(a));
  std::sort(axes.begin(), axes.end(), [&](int x, int y) { return rank[x] < rank[y]; });
  for (int a = static_cast<int>(axes.size()); a < 4; ++a) axes.push_back(a);  // padded, size 1
  for (int n = 0; n < 4; ++n) {
    s.order[n] = axes[n];
    s.reversed[axes[n]] = static_cast<size_t>(axes[n]) < dims.size() && reversed[axes[n]];
  }
}

std::optional<Header> read_header_text(const fs::path& file, const std::string& what, bool& gzipped,
                                       std::string& text) {
  for (size_t size : {kFirstHeaderRead, kMaxMrtrixHeader}) {
    FileHead head = read_file_head(file, size, what);
    gzipped = head.gzipped;
    text = std::move(head.bytes);
    std::optional<Header> h = parse_header_text(text, what);
    if (h || text.size() < size) return h;
  }
  return std::nullopt;
}

// dim: the image's axes; MRtrix pads fewer than 3 with size 1. The first four sizes go to `s`.
std::vector<int64_t> parse_dims(const Header& h, MrtrixStorage& s) {
  const std::string& dim_text = h.require("dim");
  std::vector<int64_t> dims;
  for (std::string_view e : entries(dim_text)) {
    const std::optional<long long> n = parse_header_number<long long>(e);
    if (!n || *n < 1 || *n > static_cast<long long>(kMaxVoxels))
      throw h.bad("dim", dim_text, "must be positive integers");
    dims.push_back(*n);
  }
  if (dims.size() > kMaxAxes)
    throw h.bad("dim", dim_text, fmt::format("has more than {} axes", kMaxAxes));
  for (size_t a = 4; a < dims.size(); ++a)
    if (dims[a] != 1)
      throw h.bad("dim", dim_text,
                  fmt::format("has {} values along axis {}; volumes are read along the 4th axis "
                              "only",
                              dims[a], a));
  for (size_t a = 0; a < 4 && a < dims.size(); ++a) s.dim[a] = dims[a];
  if (static_cast<double>(s.dim[0]) * s.dim[1] * s.dim[2] > static_cast<double>(kMaxVoxels))
    throw h.bad("dim", dim_text, fmt::format("gives more than {} voxels", kMaxVoxels));
  const glm::ivec3 grid(static_cast<int>(s.dim[0]), static_cast<int>(s.dim[1]),
                        static_cast<int>(s.dim[2]));
  check_frame_count(grid, s.dim[3], h.what);
  return dims;
}

// vox: as MRtrix sanitises it: a missing or non-finite spacing of the first three axes
// becomes the mean of the finite ones (1 when none is).
std::array<double, 3> parse_spacing(const Header& h, size_t ndim) {
  const std::string& vox_text = h.require("vox");
  const std::vector<double> vox = parse_floats(h, "vox", vox_text);
  if (vox.size() < std::min<size_t>(3, ndim))
    throw h.bad("vox", vox_text, fmt::format("has {} entries for {} axes", vox.size(), ndim));
  std::array<double, 3> spacing{NAN, NAN, NAN};
  for (size_t a = 0; a < vox.size() && a < ndim; ++a) {
    if (vox[a] < 0.0) throw h.bad("vox", vox_text, "holds a negative voxel size");
    if (a < 3) spacing[a] = vox[a];
  }
  double sum = 0.0;
  int finite = 0;
  for (double v : spacing)
    if (std::isfinite(v)) sum += v, ++finite;
  for (double& v : spacing)
    if (!std::isfinite(v)) v = finite ? sum / finite : 1.0;
  return spacing;
}

// transform: three (or more) rows of four, scanner RAS of the unit axes and of voxel 0; its
// columns are scaled by the spacing. Absent or not finite: MRtrix's default, the grid
// centred on the origin. Returned as LPS.
glm::dmat4 parse_transform(const Header& h, const MrtrixStorage& s,
                           const std::array<double, 3>& spacing) {
  glm::dmat4 m(1.0);
  bool have_transform = false;
  if (!h.transform.empty()) {
    if (h.transform.size() < 3)
      throw h.bad(
          "transform", h.transform.front(),
          fmt::format("is given in {} rows; 3 rows of 4 values are needed", h.transform.size()));
    have_transform = true;
    for (int r = 0; r < 3; ++r) {
      const std::vector<double> row = parse_floats(h, "transform", h.transform[r]);
      if (row.size() != 4)
        throw h.bad("transform", h.transform[r], fmt::format("has {} values, not 4", row.size()));
      for (int c = 0; c < 4; ++c) {
        m[c][r] = row[c];
        have_transform = have_transform && std::isfinite(row[c]);
      }
    }
  }
  if (!have_transform) {
    m = glm::dmat4(1.0);
    for (int a = 0; a < 3; ++a) m[3][a] = -0.5 * static_cast<double>(s.dim[a] - 1) * spacing[a];
  }
  for (int a = 0; a < 3; ++a) m[a] *= spacing[a];
  m[3][3] = 1.0;
  for (int c = 0; c < 4; ++c) {  // scanner RAS -> LPS
    m[c][0] = -m[c][0];
    m[c][1] = -m[c][1];
  }
  return m;
}

// scaling: "offset,scale", applied as offset + scale * value.
void parse_scaling(const Header& h, MrtrixLayout& l) {
  if (auto it = h.keys.find("scaling"); it != h.keys.end()) {
    const std::vector<double> v = parse_floats(h, "scaling", it->second);
    if (v.size() != 2) throw h.bad("scaling", it->second, "must be two numbers: offset,scale");
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]))
      throw h.bad("scaling", it->second, "holds a non-finite number");
    l.offset = v[0];
    l.scale = v[1];
  }
}

// file: ". OFFSET" (this file, after END) or "NAME [OFFSET]" beside the header.
void parse_data_file(const Header& h, const fs::path& file, bool gzipped, MrtrixStorage& s) {
  const std::string& what = h.what;
  if (h.files.empty()) throw Error(fmt::format("{}: missing key 'file'", what));
  if (h.files.size() > 1)
    throw h.bad("file", h.files[1],
                "is a second data file; data split over files is not supported");
  const std::vector<std::string_view> words = split_words(h.files.front());
  std::optional<long long> offset = 0;
  if (words.empty() || words.size() > 2 ||
      (words.size() == 2 && !(offset = parse_header_number<long long>(words[1]))) || *offset < 0)
    throw h.bad("file", h.files.front(), "must be a file name and a byte offset");
  s.offset = static_cast<uint64_t>(*offset);
  if (words[0] == ".") {
    if (s.offset < h.end)
      throw h.bad("file", h.files.front(),
                  fmt::format("puts the data at byte {}, inside the header (which ends at {})",
                              s.offset, h.end));
    s.file = file;
    s.what = what;
    s.gzipped = gzipped;
  } else {
    if (gzipped)
      throw h.bad("file", h.files.front(),
                  "names another file; a gzipped MRtrix image holds its data after its header");
    if (words[0].find('[') != std::string_view::npos)
      throw h.bad("file", h.files.front(), "names a numbered series of files, not supported");
    s.file = resolve_data_file(file, std::string(words[0]), "field 'file'");
    s.what = fmt::format("{} (data file of {})", s.file.string(), what);
    s.gzipped = read_file_head(s.file, 0, s.what).gzipped;
  }
}

}  // namespace

MrtrixLayout read_mrtrix_layout(const fs::path& file) {
  const std::string what = file.string();
  require_regular_file(file, what);
  bool gzipped = false;
  std::string text;
  const std::optional<Header> parsed = read_header_text(file, what, gzipped, text);
  if (!parsed)
    throw Error(fmt::format("{}: the header has no END line{}", what,
                            text.size() >= kMaxMrtrixHeader
                                ? fmt::format(" within its first {} bytes", kMaxMrtrixHeader)
                                : " (truncated file?)"));
  const Header& h = *parsed;

  MrtrixLayout l;
  MrtrixStorage& s = l.data;
  const std::vector<int64_t> dims = parse_dims(h, s);
  const std::array<double, 3> spacing = parse_spacing(h, dims.size());
  const DataType dt = parse_datatype(h);
  s.type = dt.type;
  s.swap = dt.big_endian && raw_type_size(dt.type) > 1;
  parse_layout(h, dims, s);
  const glm::dmat4 m = parse_transform(h, s, spacing);
  parse_scaling(h, l);
  parse_data_file(h, file, gzipped, s);

  l.header.dims = glm::ivec3(static_cast<int>(s.dim[0]), static_cast<int>(s.dim[1]),
                             static_cast<int>(s.dim[2]));
  l.header.type = l.scaled() ? VoxelType::f32 : storage_type_for(s.type);
  l.header.index_to_world = m;
  l.header.frames = static_cast<int>(s.dim[3]);
  return l;
}

bool is_mrtrix_header(std::string_view first_bytes) {
  if (!first_bytes.starts_with(kMagic)) return false;
  const std::string_view rest = first_bytes.substr(kMagic.size());
  return rest.empty() || rest.front() == '\n' || rest.front() == '\r';
}

}  // namespace imx::detail
