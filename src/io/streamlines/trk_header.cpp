#include "io/streamlines/trk_header.hpp"

#include <algorithm>
#include <charconv>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streamlines/stored_values.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {
namespace {

// Byte offsets of the fields nibabel's header_2_dtype lays out.
constexpr size_t kDims = 6, kVoxelSizes = 12, kNScalars = 36, kScalarNames = 38, kNProperties = 238,
                 kPropertyNames = 240, kVoxToRas = 440, kVoxelOrder = 948, kNCount = 988,
                 kVersion = 992, kHdrSize = 996;
constexpr size_t kNameBytes = 20, kNames = 10;

// numpy's S<n> fields drop their trailing NULs.
std::string_view fixed_string(std::string_view bytes, size_t at, size_t size) {
  std::string_view s = bytes.substr(at, size);
  while (!s.empty() && s.back() == '\0') s.remove_suffix(1);
  return s;
}

std::string latin1_to_utf8(std::string_view s) {
  std::string out;
  for (char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x80) {
      out += ch;
    } else {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

// nibabel's decode_value_from_name for each of the ten names, and its dict of slices: a name
// seen again takes the later columns; values no name claims are `rest`.
std::vector<TrkValueColumns> value_columns(std::string_view bytes, size_t at, int total,
                                           const char* field, const char* rest,
                                           const std::string& what,
                                           std::vector<std::string>& notes) {
  std::vector<TrkValueColumns> columns;
  if (total <= 0) return columns;
  auto assign = [&](std::string name, int first, int count, bool packed) {
    auto same = std::find_if(columns.begin(), columns.end(),
                             [&](const TrkValueColumns& c) { return c.name == name; });
    if (same != columns.end())
      *same = {std::move(name), first, count, packed};
    else
      columns.push_back({std::move(name), first, count, packed});
  };
  int next = 0;
  for (size_t i = 0; i < kNames; ++i) {
    const std::string_view raw = fixed_string(bytes, at + i * kNameBytes, kNameBytes);
    if (raw.empty()) continue;
    const size_t nul = raw.find('\0');
    std::string_view name = raw.substr(0, nul);
    int count = 1;
    if (nul != std::string_view::npos) {
      const std::string_view digits = trim(raw.substr(nul + 1));
      if (digits.find('\0') != std::string_view::npos)
        throw Error(fmt::format("{}: {} {} '{}': bytes after its value count should be NUL", what,
                                field, i, shown(raw)));
      const char* end = digits.data() + digits.size();
      auto [stop, ec] =
          std::from_chars(digits.data() + (digits.starts_with('+') ? 1 : 0), end, count);
      if (digits.empty() || ec != std::errc() || stop != end || count < 0)
        throw Error(fmt::format("{}: {} {} '{}': '{}' after the name is not a count of values",
                                what, field, i, shown(raw), shown(digits)));
    }
    if (count == 0) continue;
    // Columns past n_scalars (at most 32767) are cut off anyway: a larger count changes nothing.
    count = std::min(count, 65536);
    assign(std::string(trim(latin1_to_utf8(name))), next, count, count > 1);
    next += count;
  }
  if (next < total) assign(rest, next, total - next, total - next > 1);
  if (next > total)
    notes.push_back(
        fmt::format("{}: {} names {} values, the header stores {}: names past them "
                    "get fewer or no values",
                    what, field, next, total));
  // numpy slices past the stored columns are cut short, or empty.
  std::vector<TrkValueColumns> stored;
  for (TrkValueColumns& c : columns) {
    c.count = std::max(0, std::min(c.first + c.count, total) - std::min(c.first, total));
    if (c.count > 0)
      stored.push_back(std::move(c));
    else
      notes.push_back(
          fmt::format("{}: {} '{}' has no stored values: left out", what, field, c.name));
  }
  return stored;
}

}  // namespace

TrkHeader parse_trk_header(std::string_view bytes, const std::string& what,
                           std::vector<std::string>& notes) {
  if (!bytes.starts_with("TRACK"))
    throw Error(fmt::format("{}: not a TrackVis file (it does not start with 'TRACK')", what));
  if (bytes.size() < kTrkHeaderBytes)
    throw Error(fmt::format("{}: {} bytes is shorter than the 1000-byte TrackVis header", what,
                            bytes.size()));
  TrkHeader h;
  const char* p = bytes.data();
  // nibabel reads the header in the machine's byte order and swaps when hdr_size is not 1000.
  h.big_endian = std::endian::native == std::endian::big;
  if (load_stored<int32_t>(p + kHdrSize, h.big_endian) != 1000) {
    h.big_endian = !h.big_endian;
    if (load_stored<int32_t>(p + kHdrSize, h.big_endian) != 1000)
      throw Error(fmt::format("{}: hdr_size is {}, not 1000 in either byte order", what,
                              load_stored<int32_t>(p + kHdrSize, false)));
  }
  const bool big = h.big_endian;
  h.version = load_stored<int32_t>(p + kVersion, big);
  if (h.version < 1 || h.version > 3)
    throw Error(
        fmt::format("{}: TrackVis version {} (versions 1 and 2 are read)", what, h.version));
  if (h.version == 3)
    notes.push_back(
        fmt::format("{}: TrackVis version 3, read as version 2 (as nibabel does)", what));

  for (size_t i = 0; i < 3; ++i) {
    h.space.dims[i] = load_stored<int16_t>(p + kDims + 2 * i, big);
    h.space.voxel_sizes[i] = load_stored<float>(p + kVoxelSizes + 4 * i, big);
  }
  for (size_t r = 0; r < 4; ++r)
    for (size_t c = 0; c < 4; ++c)
      h.space.vox_to_ras[r][c] =
          h.version == 1 ? 0.0f : load_stored<float>(p + kVoxToRas + 4 * (4 * r + c), big);
  if (h.space.vox_to_ras[3][3] == 0) {
    for (size_t r = 0; r < 4; ++r)
      for (size_t c = 0; c < 4; ++c) h.space.vox_to_ras[r][c] = r == c ? 1.0f : 0.0f;
    notes.push_back(
        fmt::format("{}: vox_to_ras is not recorded ({}): taken as the identity, as nibabel does",
                    what, h.version == 1 ? "TrackVis version 1" : "its [3][3] is 0"));
  }
  h.space.voxel_order = latin1_to_utf8(fixed_string(bytes, kVoxelOrder, 4));
  if (h.space.voxel_order.empty()) {
    h.space.voxel_order = "LPS";
    notes.push_back(fmt::format(
        "{}: voxel_order is empty: taken as LPS, TrackVis's default (as nibabel does)", what));
  }

  h.n_scalars = load_stored<int16_t>(p + kNScalars, big);
  h.n_properties = load_stored<int16_t>(p + kNProperties, big);
  if (h.n_scalars < 0)
    throw Error(fmt::format("{}: n_scalars is {}, a negative count", what, h.n_scalars));
  if (h.n_properties < 0)
    throw Error(fmt::format("{}: n_properties is {}, a negative count", what, h.n_properties));
  h.scalars =
      value_columns(bytes, kScalarNames, h.n_scalars, "scalar_name", "scalars", what, notes);
  h.properties = value_columns(bytes, kPropertyNames, h.n_properties, "property_name", "properties",
                               what, notes);
  h.n_count = load_stored<int32_t>(p + kNCount, big);
  if (h.n_count < 0)
    throw Error(
        fmt::format("{}: n_count is {}, a negative number of streamlines", what, h.n_count));
  return h;
}

}  // namespace imx::detail
