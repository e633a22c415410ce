#include <algorithm>
#include <cctype>
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
#include <glm/mat3x3.hpp>

#include "intermix/error.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/inflate_charge.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"
#include "io/volume/metaimage.hpp"
#include "io/voxels/frames.hpp"
#include "io/voxels/mapped_voxels.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace {

// MetaImage keys are words such as ElementSpacing; anything else is not a header line.
bool is_key(std::string_view key) {
  return !key.empty() && std::all_of(key.begin(), key.end(),
                                     [](unsigned char c) { return std::isalnum(c) || c == '_'; });
}

struct Header {
  std::map<std::string, std::string> fields;  // key (lower case) -> trimmed value
  std::streamoff data_offset = 0;             // where attached (LOCAL) data begins
  std::string what;                           // the file, for messages

  const std::string* find(std::string_view key) const {
    auto it = fields.find(lower(key));
    return it == fields.end() ? nullptr : &it->second;
  }
  // The first of several synonymous keys that is present, with the name it was found under.
  std::pair<const std::string*, std::string_view> find_any(
      std::initializer_list<std::string_view> keys) const {
    for (std::string_view k : keys)
      if (const std::string* v = find(k)) return {v, k};
    return {nullptr, *keys.begin()};
  }
  const std::string& require(std::string_view key) const {
    if (const std::string* v = find(key)) return *v;
    throw Error(fmt::format("{}: missing key '{}'", what, key));
  }
  Error bad(std::string_view key, std::string_view value, const std::string& why) const {
    return Error(fmt::format("{}: key '{}' value '{}' {}", what, key, shown(value), why));
  }
};

// Reads "Key = Value" lines up to and including ElementDataFile, which MetaImage puts last.
Header read_header(std::istream& in, const std::string& what) {
  Header h;
  h.what = what;
  std::string line;
  size_t total = 0;
  bool first = true;
  while (true) {
    line.clear();
    int c;
    bool got = false;
    while ((c = in.get()) != std::char_traits<char>::eof()) {
      got = true;
      if (c == '\n') break;
      if (line.size() >= kMaxHeaderLineBytes)
        throw Error(fmt::format("{}: header line longer than {} bytes (not a MetaImage header?)",
                                what, kMaxHeaderLineBytes));
      line.push_back(static_cast<char>(c));
    }
    if (!got)
      throw Error(fmt::format("{}: missing key 'ElementDataFile' (the header's last)", what));
    total += line.size() + 1;
    if (total > kMaxHeaderBytes)
      throw Error(fmt::format("{}: header longer than {} bytes (missing 'ElementDataFile'?)", what,
                              kMaxHeaderBytes));
    std::string_view l = trim(line);
    if (l.empty()) continue;
    size_t eq = l.find('=');
    if (eq == std::string_view::npos || !is_key(trim(l.substr(0, eq)))) {
      if (first)
        throw Error(
            fmt::format("{}: not a MetaImage file (expected 'Key = Value' lines such as "
                        "'ObjectType = Image')",
                        what));
      throw Error(fmt::format("{}: header line '{}' is not 'Key = Value'", what, shown(l)));
    }
    first = false;
    std::string key = lower(trim(l.substr(0, eq)));
    if (!h.fields.emplace(key, std::string(trim(l.substr(eq + 1)))).second)
      throw Error(fmt::format("{}: key '{}' appears twice", what, trim(l.substr(0, eq))));
    if (key == "elementdatafile") break;
  }
  h.data_offset = in.tellg();
  return h;
}

RawType parse_element_type(const Header& h) {
  static const std::map<std::string, RawType> names = {
      {"MET_CHAR", RawType::i8},       {"MET_UCHAR", RawType::u8},
      {"MET_SHORT", RawType::i16},     {"MET_USHORT", RawType::u16},
      {"MET_INT", RawType::i32},       {"MET_UINT", RawType::u32},
      {"MET_LONG", RawType::i32},      {"MET_ULONG", RawType::u32},
      {"MET_LONG_LONG", RawType::i64}, {"MET_ULONG_LONG", RawType::u64},
      {"MET_FLOAT", RawType::f32},     {"MET_DOUBLE", RawType::f64}};
  const std::string& value = h.require("ElementType");
  std::string upper(value);
  std::transform(upper.begin(), upper.end(), upper.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  auto it = names.find(upper);
  if (it == names.end())
    throw h.bad("ElementType", value,
                "is not supported (supported: MET_CHAR, MET_UCHAR, MET_SHORT, MET_USHORT, "
                "MET_INT, MET_UINT, MET_LONG, MET_ULONG, MET_LONG_LONG, MET_ULONG_LONG, "
                "MET_FLOAT, MET_DOUBLE)");
  return it->second;
}

bool parse_bool(const Header& h, std::string_view key, const std::string& value) {
  std::string v = lower(value);
  if (v == "true" || v == "1") return true;
  if (v == "false" || v == "0") return false;
  throw h.bad(key, value, "must be True or False");
}

bool optional_bool(const Header& h, std::initializer_list<std::string_view> keys) {
  auto [value, key] = h.find_any(keys);
  return value ? parse_bool(h, key, *value) : false;
}

// Exactly `n` finite numbers.
std::vector<double> parse_numbers(const Header& h, std::string_view key, const std::string& value,
                                  size_t n) {
  auto words = split_words(value);
  if (words.size() != n)
    throw h.bad(key, value, fmt::format("has {} numbers, expected {}", words.size(), n));
  std::vector<double> out;
  for (std::string_view w : words) {
    std::optional<double> v = parse_header_number<double>(w);
    if (!v) throw h.bad(key, value, fmt::format("holds '{}', which is not a number", shown(w)));
    if (!std::isfinite(*v)) throw h.bad(key, value, "holds a non-finite number (NaN or infinity)");
    out.push_back(*v);
  }
  return out;
}

glm::ivec3 parse_dims(const Header& h, int ndims, size_t& count) {
  const std::string& value = h.require("DimSize");
  auto words = split_words(value);
  if (words.size() != static_cast<size_t>(ndims))
    throw h.bad("DimSize", value, fmt::format("has {} sizes, NDims is {}", words.size(), ndims));
  glm::ivec3 dims(1);
  count = 1;
  for (int a = 0; a < ndims; ++a) {
    std::optional<long long> n = parse_header_number<long long>(words[a]);
    if (!n || *n <= 0 || *n > static_cast<long long>(kMaxVoxels))
      throw h.bad("DimSize", value, "must be positive integers");
    dims[a] = static_cast<int>(*n);
    // Compared before multiplying: 2^40 times a size up to 2^31 would overflow.
    if (static_cast<double>(count) * static_cast<double>(*n) > static_cast<double>(kMaxGridVoxels))
      throw h.bad("DimSize", value, fmt::format("gives more than {} voxels", kMaxGridVoxels));
    count *= static_cast<size_t>(*n);
  }
  return dims;
}

// Index to world from ElementSpacing, Offset and TransformMatrix, whose rows are the direction
// cosines of the index axes (ITK's layout); a 2D image becomes one slice at z = 0.
glm::dmat4 parse_affine(const Header& h, int ndims) {
  const size_t n = static_cast<size_t>(ndims);
  std::vector<double> spacing(n, 1.0), offset(n, 0.0), matrix(n * n, 0.0);
  for (size_t a = 0; a < n; ++a) matrix[a * n + a] = 1.0;
  if (auto [v, key] = h.find_any({"ElementSpacing", "ElementSize"}); v) {
    spacing = parse_numbers(h, key, *v, n);
    for (double s : spacing)
      if (s <= 0.0) throw h.bad(key, *v, "must be positive");
  }
  if (auto [v, key] = h.find_any({"Offset", "Position", "Origin"}); v)
    offset = parse_numbers(h, key, *v, n);
  std::string_view matrix_key = "TransformMatrix";
  std::string matrix_value = "(absent: identity)";
  if (auto [v, key] = h.find_any({"TransformMatrix", "Rotation", "Orientation"}); v) {
    matrix = parse_numbers(h, key, *v, n * n);
    matrix_key = key;
    matrix_value = *v;
  }
  glm::dmat4 m(1.0);
  for (size_t a = 0; a < n; ++a) {
    for (size_t r = 0; r < n; ++r) m[a][r] = matrix[a * n + r] * spacing[a];
    m[3][a] = offset[a];
  }
  if (std::abs(glm::determinant(glm::dmat3(m))) < 1e-12)
    throw h.bad(matrix_key, matrix_value,
                "gives a singular index-to-world transform (parallel or zero axes)");
  return m;
}

// What the header says about the volume and where its voxels are.
struct Layout {
  VolumeHeader header;
  RawType type = RawType::u8;
  bool big_endian = false, compressed = false;
};

// Checks the header's keys and reads the volume's dims, type and placement from them.
Layout parse_layout(const Header& h) {
  if (const std::string* type = h.find("ObjectType"); type && lower(*type) != "image")
    throw h.bad("ObjectType", *type, "is not supported (only Image)");
  const std::string& ndims_text = h.require("NDims");
  std::optional<int> ndims = parse_header_number<int>(trim(ndims_text));
  if (!ndims || (*ndims != 2 && *ndims != 3))
    throw h.bad("NDims", ndims_text, "is not supported (only 2 or 3)");
  if (const std::string* ch = h.find("ElementNumberOfChannels"); ch && trim(*ch) != "1")
    throw h.bad("ElementNumberOfChannels", *ch, "is not supported (only scalar images, 1)");
  if (const std::string* binary = h.find("BinaryData");
      binary && !parse_bool(h, "BinaryData", *binary))
    throw h.bad("BinaryData", *binary, "is not supported (only binary voxel data)");

  Layout l;
  size_t count = 0;
  l.header.dims = parse_dims(h, *ndims, count);
  l.type = parse_element_type(h);
  l.header.type = storage_type_for(l.type);
  l.header.index_to_world = parse_affine(h, *ndims);
  l.big_endian = optional_bool(h, {"BinaryDataByteOrderMSB", "ElementByteOrderMSB"});
  l.compressed = optional_bool(h, {"CompressedData"});
  return l;
}

// The voxels of `box` from the data the header locates: after the header in `in` (LOCAL), or in
// one file named relative to the header.
VoxelStorage read_voxels(const std::filesystem::path& file, std::ifstream& in, const Header& h,
                         const Layout& layout, const VoxelBox& box) {
  const std::string& what = h.what;
  const glm::ivec3 dims = layout.header.dims;
  require_loadable_box(box, what);
  const std::string& data_name = h.require("ElementDataFile");
  std::filesystem::path data_path = file;
  std::streamoff start = h.data_offset;
  std::string data_what = what;
  if (lower(data_name) != "local") {
    if (lower(data_name).rfind("list", 0) == 0 || data_name.find('%') != std::string::npos)
      throw h.bad("ElementDataFile", data_name,
                  "lists several files; only LOCAL or one data file is supported");
    data_path = resolve_data_file(file, data_name, "field 'ElementDataFile'");
    data_what = fmt::format("{} (data file of {})", data_path.string(), what);
    in = open_input_stream(data_path, data_what);
    start = 0;
  } else if (start < 0) {
    throw Error(fmt::format("{}: the header ends at 'ElementDataFile = LOCAL' with no data", what));
  }

  std::error_code ec;
  uintmax_t file_size = std::filesystem::file_size(data_path, ec);
  if (ec)
    throw Error(fmt::format("{}: cannot read the size of the data: {}", data_what, ec.message()));
  const size_t needed = static_cast<size_t>(dims.x) * dims.y * dims.z * raw_type_size(layout.type);
  long long header_size = 0;
  if (const std::string* hs = h.find("HeaderSize")) {
    std::optional<long long> n = parse_header_number<long long>(trim(*hs));
    if (!n || *n < -1) throw h.bad("HeaderSize", *hs, "must be an integer >= -1");
    if (*n == -1 && layout.compressed)
      throw h.bad("HeaderSize", *hs, "-1 (data at the end of the file) needs uncompressed data");
    header_size = *n == -1 ? static_cast<long long>(file_size) - static_cast<long long>(needed) -
                                 static_cast<long long>(start)
                           : *n;
    header_size = std::max(header_size, 0LL);
  }
  size_t offset = static_cast<size_t>(start) + static_cast<size_t>(header_size);
  size_t available = file_size > offset ? static_cast<size_t>(file_size - offset) : 0;

  if (!layout.compressed) {
    // The whole grid's data must be there, as for a whole read, even when the box needs less.
    if (available < needed)
      throw Error(fmt::format(
          "{}: expected {} bytes of voxel data ({}x{}x{} {}), found {} "
          "(truncated file?)",
          data_what, needed, dims.x, dims.y, dims.z, raw_type_name(layout.type), available));
    // Native, uncompressed and whole: viewed in place.
    if (!layout.big_endian && box == VoxelBox::whole(dims))
      if (auto mapped = map_voxels(data_path, offset, layout.type, box.count()))
        return std::move(*mapped);
    return load_raw_voxels(in, offset, layout.type, dims, box, layout.big_endian, data_what);
  }
  if (const std::string* cds = h.find("CompressedDataSize")) {
    std::optional<long long> n = parse_header_number<long long>(trim(*cds));
    if (!n || *n <= 0) throw h.bad("CompressedDataSize", *cds, "must be a positive integer");
    if (static_cast<unsigned long long>(*n) > available)
      throw Error(
          fmt::format("{}: key 'CompressedDataSize' says {} bytes of compressed data, "
                      "found {} (truncated file?)",
                      data_what, *n, available));
    available = static_cast<size_t>(*n);
  }
  check_inflatable(needed, available, data_what);
  refuse_compressed_claim(needed, VoxelBox::whole(dims).count() > kMaxVoxels, data_what,
                          "compressed voxel data");
  in.clear();
  in.seekg(static_cast<std::streamoff>(offset));
  return load_gzip_voxels(in, 0, layout.type, dims, box, layout.big_endian, data_what);
}

std::ifstream open_header(const std::filesystem::path& file) {
  std::ifstream in = open_input_stream(file, file.string());
  return in;
}

}  // namespace

VolumeHeader read_metaimage_header(const std::filesystem::path& file) {
  const std::string what = file.string();
  std::ifstream in = open_header(file);
  VolumeHeader header = parse_layout(read_header(in, what)).header;
  check_placement(header.index_to_world, what);
  return header;
}

VolumeData read_metaimage_region(const std::filesystem::path& file, const VoxelBox& box,
                                 int frame) {
  require_frame(frame, 1, file.string());
  const std::string what = file.string();
  std::ifstream in = open_header(file);
  const Header h = read_header(in, what);
  const Layout layout = parse_layout(h);
  require_box_inside(layout.header.dims, box, what);
  VolumeData v;
  v.dims = box.size();
  v.index_to_world = box_index_to_world(layout.header.index_to_world, box.lo);
  v.voxels = read_voxels(file, in, h, layout, box);
  v.validate(what);
  return v;
}

VolumeData read_metaimage(const std::filesystem::path& file, int frame) {
  require_frame(frame, 1, file.string());
  const std::string what = file.string();
  std::ifstream in = open_header(file);
  const Header h = read_header(in, what);
  const Layout layout = parse_layout(h);
  VolumeData v;
  v.dims = layout.header.dims;
  v.index_to_world = layout.header.index_to_world;
  v.voxels = read_voxels(file, in, h, layout, VoxelBox::whole(v.dims));
  v.validate(what);
  return v;
}

}  // namespace imx::detail
