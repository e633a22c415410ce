// TrackVis .trk (trk.hpp): the header, a walk over the streamlines that checks every count
// against the file before anything is allocated, then one pass that converts them in place.
#include <cmath>
#include <cstdint>
#include <limits>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streamlines/mapped_file.hpp"
#include "io/streamlines/stored_values.hpp"
#include "io/streamlines/streamline_drops.hpp"
#include "io/streamlines/trk.hpp"
#include "io/streamlines/trk_header.hpp"

namespace imx::detail {
namespace {

struct Layout {
  uint64_t streamlines = 0;
  uint64_t points = 0;
  uint64_t end = 0;  // the byte after the last streamline read
};

// Where the streamlines lie: n_count of them (0: to the end of the file), each one inside it.
Layout walk_streamlines(std::string_view bytes, const TrkHeader& h, const std::string& what) {
  const uint64_t point_bytes = 4 * (3 + uint64_t(h.n_scalars));
  const uint64_t property_bytes = 4 * uint64_t(h.n_properties);
  const uint64_t size = bytes.size();
  if (h.n_count > 0 && uint64_t(h.n_count) * (4 + property_bytes) > size - kTrkHeaderBytes)
    throw Error(fmt::format(
        "{}: n_count says {} streamlines, more than the {} bytes after the header can hold", what,
        h.n_count, size - kTrkHeaderBytes));
  const uint64_t wanted =
      h.n_count > 0 ? uint64_t(h.n_count) : std::numeric_limits<uint64_t>::max();
  Layout l;
  uint64_t at = kTrkHeaderBytes;
  while (l.streamlines < wanted) {
    if (at == size) {
      if (h.n_count > 0)
        throw Error(fmt::format("{}: n_count says {} streamlines, the file ends after {}", what,
                                h.n_count, l.streamlines));
      break;
    }
    if (size - at < 4)
      throw Error(
          fmt::format("{}: the file ends inside the point count of streamline {} ({} bytes left)",
                      what, l.streamlines, size - at));
    const int32_t n = load_stored<int32_t>(bytes.data() + at, h.big_endian);
    if (n < 0)
      throw Error(fmt::format("{}: streamline {} has a point count of {}", what, l.streamlines, n));
    const uint64_t need = uint64_t(n) * point_bytes + property_bytes;
    if (need > size - at - 4)
      throw Error(fmt::format(
          "{}: streamline {} claims {} points ({} bytes with its values), only {} bytes are left "
          "at byte {}",
          what, l.streamlines, n, need, size - at - 4, at + 4));
    at += 4 + need;
    l.points += uint64_t(n);
    ++l.streamlines;
  }
  l.end = at;
  return l;
}

struct Affine {
  double m[3][4];  // rows of the voxmm -> RAS map
};

// Converts every streamline into `out`, leaving out those of fewer than 2 points or with a
// coordinate that is not finite (in RAS, after the map).
template <bool BigEndian>
void convert_streamlines(std::string_view bytes, const TrkHeader& h, const Layout& l,
                         const Affine& a, Streamlines& out, StreamlineDrops& drops) {
  const size_t values = 3 + size_t(h.n_scalars);
  const size_t point_bytes = 4 * values;
  // One output array per stored column.
  std::vector<float*> scalar_out, property_out;
  for (StreamlineValues& v : out.point_values) scalar_out.push_back(v.values.data());
  for (StreamlineValues& v : out.streamline_values) property_out.push_back(v.values.data());
  std::vector<int> scalar_columns, property_columns;
  for (const TrkValueColumns& c : h.scalars)
    for (int i = 0; i < c.count; ++i) scalar_columns.push_back(c.first + i);
  for (const TrkValueColumns& c : h.properties)
    for (int i = 0; i < c.count; ++i) property_columns.push_back(c.first + i);

  glm::vec3* points = out.points.data();
  size_t kept_points = 0, kept = 0;
  const char* at = bytes.data() + kTrkHeaderBytes;
  for (uint64_t s = 0; s < l.streamlines; ++s) {
    const auto n = static_cast<size_t>(load_stored<int32_t, BigEndian>(at));
    at += 4;
    const char* first = at;
    bool finite = true;
    for (size_t k = 0; k < n; ++k, at += point_bytes) {
      const double x = load_stored<float, BigEndian>(at), y = load_stored<float, BigEndian>(at + 4),
                   z = load_stored<float, BigEndian>(at + 8);
      const auto ras = [&](int r) {
        return static_cast<float>(a.m[r][0] * x + a.m[r][1] * y + a.m[r][2] * z + a.m[r][3]);
      };
      const glm::vec3 p(-ras(0), -ras(1), ras(2));
      finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
      points[kept_points + k] = p;
    }
    const bool keep = n >= 2 && finite;
    if (!keep) {
      if (n < 2)
        drops.too_short(s);
      else
        drops.not_finite(s);
    } else {
      for (size_t c = 0; c < scalar_columns.size(); ++c) {
        const char* value = first + 4 * (3 + scalar_columns[c]);
        float* dst = scalar_out[c] + kept_points;
        for (size_t k = 0; k < n; ++k, value += point_bytes)
          dst[k] = load_stored<float, BigEndian>(value);
      }
      for (size_t c = 0; c < property_columns.size(); ++c)
        property_out[c][kept] = load_stored<float, BigEndian>(at + 4 * property_columns[c]);
      kept_points += n;
      ++kept;
      out.offsets.push_back(static_cast<uint32_t>(kept_points));
    }
    at += 4 * size_t(h.n_properties);
  }
  out.points.resize(kept_points);
  for (StreamlineValues& v : out.point_values) v.values.resize(kept_points);
  for (StreamlineValues& v : out.streamline_values) v.values.resize(kept);
}

// "fa", or "rgb[0]" .. "rgb[2]" for a name of several values.
void name_arrays(const std::vector<TrkValueColumns>& columns, size_t size,
                 std::vector<StreamlineValues>& arrays) {
  for (const TrkValueColumns& c : columns)
    for (int i = 0; i < c.count; ++i)
      arrays.push_back(
          {c.packed ? fmt::format("{}[{}]", c.name, i) : c.name, std::vector<float>(size)});
}

}  // namespace

Streamlines read_trk(const std::filesystem::path& file, std::vector<std::string>& notes) {
  const std::string what = file.string();
  const MappedFile map(file);
  const std::string_view bytes = map.bytes();
  const TrkHeader h = parse_trk_header(bytes, what, notes);
  const glm::dmat4 voxmm_to_ras = trk_voxmm_to_ras(h.space, what);
  const Layout l = walk_streamlines(bytes, h, what);
  if (l.end < bytes.size())
    notes.push_back(fmt::format("{}: {} bytes after the {} streamlines of n_count are ignored",
                                what, bytes.size() - l.end, h.n_count));
  if (l.points > std::numeric_limits<uint32_t>::max())
    throw Error(
        fmt::format("{}: {} points, more than the 2^32 intermix can index", what, l.points));
  size_t scalar_arrays = 0, property_arrays = 0;
  for (const TrkValueColumns& c : h.scalars) scalar_arrays += size_t(c.count);
  for (const TrkValueColumns& c : h.properties) property_arrays += size_t(c.count);
  check_memory(l.points * (sizeof(glm::vec3) + 4 * scalar_arrays) +
                   l.streamlines * (4 + 4 * property_arrays),
               what);

  Affine a{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) a.m[r][c] = voxmm_to_ras[c][r];
  Streamlines out;
  out.points.resize(l.points);
  out.offsets.reserve(l.streamlines + 1);
  name_arrays(h.scalars, l.points, out.point_values);
  name_arrays(h.properties, l.streamlines, out.streamline_values);
  StreamlineDrops drops;
  if (h.big_endian)
    convert_streamlines<true>(bytes, h, l, a, out, drops);
  else
    convert_streamlines<false>(bytes, h, l, a, out, drops);
  drops.report(what, notes);
  return out;
}

}  // namespace imx::detail
