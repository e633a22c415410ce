// FreeSurfer annotations (.annot): a label per vertex, coded as a packed RGB colour, and the
// colour table that names the colours.
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/overlay/vertex_overlay.hpp"
#include "io/streams/byte_cursor.hpp"

namespace imx::detail {
namespace {

constexpr int32_t kMaxNameBytes = 4096;

// A length-prefixed name; the file's NUL and anything after it are dropped.
std::string read_name(ByteCursor& in, const char* field) {
  const int32_t length = in.read<int32_t>(field);
  if (length < 0 || length > kMaxNameBytes)
    throw Error(
        fmt::format("{}: {} has length {}, not 0 to {}", in.what(), field, length, kMaxNameBytes));
  std::string name(in.take(static_cast<size_t>(length), field));
  return name.substr(0, name.find('\0'));
}

OverlayLabel read_entry(ByteCursor& in, int64_t key) {
  OverlayLabel l;
  l.key = key;
  l.name = read_name(in, "a colour table entry's name");
  int32_t rgbt[4];
  for (int32_t& c : rgbt) {
    c = in.read<int32_t>("a colour table entry's colour");
    if (c < 0 || c > 255)
      throw Error(fmt::format("{}: colour table entry {} ('{}') has a component {} outside 0..255",
                              in.what(), key, l.name, c));
  }
  // R, G, B and T, the transparency (255 - alpha).
  l.rgba = {rgbt[0] / 255.0f, rgbt[1] / 255.0f, rgbt[2] / 255.0f, (255 - rgbt[3]) / 255.0f};
  return l;
}

}  // namespace

VertexOverlay read_freesurfer_annot(const std::string& bytes, const std::string& what) {
  ByteCursor in(bytes, what, true);
  const int32_t vnum = in.read<int32_t>("the vertex count");
  if (vnum <= 0) throw Error(fmt::format("{}: {} vertices is not a surface's", what, vnum));
  in.need(uint64_t{8} * static_cast<uint64_t>(vnum), fmt::format("{} (vertex, label) pairs", vnum));
  check_memory(uint64_t{16} * static_cast<uint64_t>(vnum), what);
  std::vector<int32_t> packed(static_cast<size_t>(vnum), 0);
  for (int32_t i = 0; i < vnum; ++i) {
    const int32_t vertex = in.read<int32_t>("a vertex index");
    const int32_t value = in.read<int32_t>("a vertex's label");
    if (vertex < 0 || vertex >= vnum)
      throw Error(fmt::format("{}: pair {} names vertex {}, but the file has {} vertices", what, i,
                              vertex, vnum));
    packed[static_cast<size_t>(vertex)] = value;
  }
  if (in.remaining() < 4 || in.read<int32_t>("the colour table flag") == 0)
    throw Error(fmt::format("{}: the annotation has no colour table", what));
  VertexOverlay out;
  out.labels = true;
  out.claimed_vertices = static_cast<uint64_t>(vnum);
  const int32_t entries = in.read<int32_t>("the colour table's entry count or version");
  // Each entry takes at least 20 bytes (name length and RGBT), so the count is bounded.
  auto check_count = [&](int64_t n, const char* field) {
    if (n < 0 || static_cast<uint64_t>(n) > in.remaining() / 20)
      throw Error(fmt::format("{}: {} {} is more than the rest of the file holds", what, field, n));
  };
  if (entries > 0) {  // the old format: entries are numbered in order
    check_count(entries, "colour table entry count");
    read_name(in, "the colour table's file name");
    for (int32_t i = 0; i < entries; ++i) out.table.push_back(read_entry(in, i));
  } else {
    if (-static_cast<int64_t>(entries) != 2)
      throw Error(
          fmt::format("{}: colour table version {} is not 1 or 2", what, -int64_t{entries}));
    const int32_t max_index = in.read<int32_t>("the colour table's largest index");
    read_name(in, "the colour table's file name");
    const int32_t count = in.read<int32_t>("the colour table's entry count");
    check_count(count, "colour table entry count");
    for (int32_t i = 0; i < count; ++i) {
      const int32_t index = in.read<int32_t>("a colour table entry's index");
      if (index < 0 || index >= max_index)
        throw Error(fmt::format("{}: colour table entry {} has index {}, outside 0..{}", what, i,
                                index, max_index - 1));
      out.table.push_back(read_entry(in, index));
    }
  }
  // Packed colour -> entry (the first, should two entries share a colour).
  std::map<int64_t, int64_t> key_of;
  for (const OverlayLabel& l : out.table) {
    const auto r = static_cast<int64_t>(std::lround(l.rgba.r * 255.0f));
    const auto g = static_cast<int64_t>(std::lround(l.rgba.g * 255.0f));
    const auto b = static_cast<int64_t>(std::lround(l.rgba.b * 255.0f));
    key_of.emplace(r + (g << 8) + (b << 16), l.key);
  }
  out.values.resize(packed.size());
  for (size_t v = 0; v < packed.size(); ++v) {
    auto it = packed[v] == 0 ? key_of.end() : key_of.find(packed[v]);
    // 0, or a colour the table lacks, is FreeSurfer's "unknown": no label.
    out.values[v] = it == key_of.end() ? std::numeric_limits<double>::quiet_NaN()
                                       : static_cast<double>(it->second);
  }
  return out;
}

}  // namespace imx::detail
