// DSI Studio TinyTrack (.tt.gz): inflated whole (bounded), its MATLAB v4 matrices found, then the
// "track" bytes walked twice: once to count and check every record, once to decode the points.
#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <span>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streamlines/mat_v4.hpp"
#include "io/streamlines/tt.hpp"
#include "io/streams/byte_cursor.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"

namespace imx::detail {
namespace {

constexpr size_t kFirstBlock = size_t{1} << 20;
constexpr double kCoordinateUnit = 32.0;  // track coordinates are in 1/32 voxel

// The file's bytes, inflated when it starts with gzip's magic: no more than deflate can make of
// the file's size and no more than the memory budget. The gzip trailer's size (ISIZE) sizes the
// first block, so that a well-formed file is inflated into one allocation.
std::string tt_bytes(const std::filesystem::path& file, const std::string& what) {
  std::ifstream in = open_input_stream(file, what, std::ios::binary | std::ios::ate);
  const auto compressed = static_cast<uint64_t>(std::max<std::streamoff>(0, in.tellg()));
  std::array<unsigned char, 4> trailer{};
  if (compressed >= 18) {
    in.seekg(-4, std::ios::end);
    in.read(reinterpret_cast<char*>(trailer.data()), 4);
  }
  std::array<unsigned char, 2> magic{};
  in.seekg(0);
  in.read(reinterpret_cast<char*>(magic.data()), 2);
  if (!in || magic[0] != 0x1f || magic[1] != 0x8b) return read_file_bytes(file);
  in.seekg(0);

  const uint64_t budget = input_limits().max_memory;
  const uint64_t bound = std::min<uint64_t>(
      budget, static_cast<uint64_t>(kMaxInflateRatio * static_cast<double>(compressed)) + 4096);
  const uint64_t isize = uint64_t{trailer[0]} | uint64_t{trailer[1]} << 8 |
                         uint64_t{trailer[2]} << 16 | uint64_t{trailer[3]} << 24;
  // A lying ISIZE must not allocate much: tractograms deflate by about 3:1.
  const uint64_t first =
      std::min({bound, std::max<uint64_t>(isize, kFirstBlock), 64 * compressed + kFirstBlock});
  GzipStream stream(in, what);
  std::string out;
  check_memory(first, fmt::format("{} (inflated)", what));
  out.resize(static_cast<size_t>(first));
  size_t size = 0;
  std::vector<uint8_t> probe(64 * 1024);
  for (;;) {
    size += stream.read({reinterpret_cast<uint8_t*>(out.data()) + size, out.size() - size});
    if (size < out.size()) break;
    const size_t extra = stream.read(probe);
    if (extra == 0) break;
    if (size + extra > bound) {
      check_memory(size + extra, fmt::format("{} (inflated)", what));
      throw Error(fmt::format(
          "{}: inflates to more than {} bytes, more than {} bytes of gzip data can hold "
          "(deflate expands at most about 1032:1): corrupt data",
          what, bound, compressed));
    }
    const uint64_t next =
        std::min<uint64_t>(bound, std::max<uint64_t>(2 * out.size(), size + extra));
    check_memory(next, fmt::format("{} (inflated)", what));
    out.resize(static_cast<size_t>(next));
    std::memcpy(out.data() + size, probe.data(), extra);
    size += extra;
  }
  out.resize(size);
  stream.finish(size);  // the checksum, and a truncated stream said as such
  return out;
}

// Voxel (x, y, z, 1) to RAS mm, row by row.
using Affine = std::array<std::array<double, 4>, 3>;

std::string triple(const std::vector<double>& v) {
  return fmt::format("{:g} {:g} {:g}", v[0], v[1], v[2]);
}

// trans_to_mni, or DSI Studio's voxel-to-RAS matrix of its own volumes (x and y flipped about
// the grid's far corner: its voxel order is LPS) where the file has none.
Affine placement(const std::vector<MatV4Matrix>& matrices, const std::string& what,
                 std::vector<std::string>& notes) {
  std::vector<double> voxel_size;
  if (const MatV4Matrix* m = find_matrix(matrices, "voxel_size")) {
    voxel_size = mat_v4_numbers(*m, 3, what);
    for (double v : voxel_size)
      if (!(std::isfinite(v) && v > 0.0))
        throw Error(
            fmt::format("{}: voxel_size {} is not three positive sizes", what, triple(voxel_size)));
  }
  Affine a{};
  if (const MatV4Matrix* m = find_matrix(matrices, "trans_to_mni")) {
    const std::vector<double> t = mat_v4_numbers(*m, 16, what);
    for (double v : t)
      if (!std::isfinite(v))
        throw Error(fmt::format("{}: trans_to_mni holds a value that is not finite", what));
    if (t[12] != 0.0 || t[13] != 0.0 || t[14] != 0.0 || t[15] != 1.0)
      throw Error(fmt::format(
          "{}: trans_to_mni's last row is {:g} {:g} {:g} {:g}, not 0 0 0 1: not an affine", what,
          t[12], t[13], t[14], t[15]));
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) a[r][c] = t[4 * r + c];
    const glm::dmat3 linear(a[0][0], a[1][0], a[2][0], a[0][1], a[1][1], a[2][1], a[0][2], a[1][2],
                            a[2][2]);
    if (!(std::abs(glm::determinant(linear)) > 1e-12))
      throw Error(fmt::format("{}: trans_to_mni is singular", what));
    if (!voxel_size.empty()) {
      std::vector<double> scale(3);
      for (int c = 0; c < 3; ++c) scale[c] = std::hypot(a[0][c], a[1][c], a[2][c]);
      for (int c = 0; c < 3; ++c)
        if (std::abs(scale[c] - voxel_size[c]) > 0.01 * voxel_size[c]) {
          notes.push_back(fmt::format(
              "trans_to_mni scales the voxels to {} mm where voxel_size says {} mm: placed by "
              "trans_to_mni",
              triple(scale), triple(voxel_size)));
          break;
        }
    }
    return a;
  }
  const MatV4Matrix* dimension = find_matrix(matrices, "dimension");
  if (!dimension || voxel_size.empty())
    throw Error(fmt::format(
        "{}: no trans_to_mni, and no dimension and voxel_size to place the voxels by", what));
  const std::vector<double> dim = mat_v4_numbers(*dimension, 3, what);
  for (double d : dim)
    if (!(d >= 1.0 && d <= 1e6 && d == std::floor(d)))
      throw Error(fmt::format("{}: dimension {} is not three voxel counts", what, triple(dim)));
  a[0] = {-voxel_size[0], 0.0, 0.0, voxel_size[0] * (dim[0] - 1.0)};
  a[1] = {0.0, -voxel_size[1], 0.0, voxel_size[1] * (dim[1] - 1.0)};
  a[2] = {0.0, 0.0, voxel_size[2], 0.0};
  notes.push_back(fmt::format(
      "no trans_to_mni: voxels placed as DSI Studio places its own volumes (dimension {}, "
      "voxel_size {} mm, LPS voxel order): the tracking space, not MNI",
      triple(dim), triple(voxel_size)));
  return a;
}

uint32_t u32_le(const char* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  if constexpr (std::endian::native == std::endian::big) v = __builtin_bswap32(v);
  return v;
}

// Streamline records: a uint32 byte count 3n, the first point as 3 int32, then n - 1 steps of
// 3 int8, all little-endian; the next record starts 3n + 13 bytes on.
struct TrackCounts {
  uint64_t streamlines = 0;
  uint64_t points = 0;
};

TrackCounts count_track(std::string_view track, const std::string& what) {
  TrackCounts c;
  size_t pos = 0;
  while (pos < track.size()) {
    const size_t left = track.size() - pos;
    if (left < 16)
      throw Error(fmt::format(
          "{}: track: streamline {} at byte {} has {} bytes, fewer than the 16 of its size and "
          "first point",
          what, c.streamlines, pos, left));
    const uint32_t size = u32_le(track.data() + pos);
    if (size < 3 || size % 3 != 0)
      throw Error(fmt::format(
          "{}: track: streamline {} at byte {} has a size of {} bytes, not a positive multiple "
          "of 3",
          what, c.streamlines, pos, size));
    const uint64_t record = uint64_t{size} + 13;
    if (record > left)
      throw Error(fmt::format(
          "{}: track: streamline {} at byte {} claims {} points ({} bytes), but only {} bytes "
          "are left",
          what, c.streamlines, pos, size / 3, record, left));
    ++c.streamlines;
    c.points += size / 3;
    pos += static_cast<size_t>(record);
  }
  return c;
}

}  // namespace

Streamlines read_tt(const std::filesystem::path& file, std::vector<std::string>& notes) {
  const std::string what = file.string();
  const std::string bytes = tt_bytes(file, what);
  const std::vector<MatV4Matrix> matrices = read_mat_v4(bytes, what);
  const MatV4Matrix* track_matrix = find_matrix(matrices, "track");
  if (!track_matrix)
    throw Error(fmt::format("{}: no matrix 'track': not a DSI Studio TinyTrack file", what));
  if (track_matrix->kind != 0 || track_matrix->imaginary || track_matrix->precision != 5)
    throw Error(fmt::format(
        "{}: matrix 'track' has type {}{}{}, not the uint8 bytes DSI Studio writes", what,
        track_matrix->precision, track_matrix->kind, track_matrix->imaginary ? " (complex)" : ""));
  const Affine a = placement(matrices, what, notes);
  std::vector<std::string> unread;
  for (const MatV4Matrix& m : matrices)
    if (m.name != "track" && m.name != "trans_to_mni" && m.name != "voxel_size" &&
        m.name != "dimension" && m.name != "report" && m.name != "parameter_id")
      unread.push_back(m.name);
  if (!unread.empty())
    notes.push_back(fmt::format("matrices left unread: {}", fmt::join(unread, ", ")));

  const std::string_view track = track_matrix->data;
  const TrackCounts counts = count_track(track, what);
  if (counts.points > UINT32_MAX)
    throw Error(fmt::format("{}: {} points are more than intermix reads ({})", what, counts.points,
                            UINT32_MAX));
  check_memory(counts.points * sizeof(glm::vec3) + counts.streamlines * sizeof(uint32_t),
               fmt::format("{} (streamlines)", what));
  Streamlines out;
  out.points.resize(static_cast<size_t>(counts.points));
  out.offsets.reserve(static_cast<size_t>(counts.streamlines) + 1);

  // Each coefficient over 32 once, so that a point is one affine map of the integer coordinates.
  Affine s = a;
  for (auto& row : s)
    for (int c = 0; c < 3; ++c) row[c] /= kCoordinateUnit;
  size_t written = 0;
  uint64_t too_short = 0, not_finite = 0;
  const char* p = track.data();
  const char* const end = p + track.size();
  while (p < end) {
    const uint32_t n = u32_le(p) / 3;
    int64_t x = static_cast<int32_t>(u32_le(p + 4));
    int64_t y = static_cast<int32_t>(u32_le(p + 8));
    int64_t z = static_cast<int32_t>(u32_le(p + 12));
    const auto* step = reinterpret_cast<const int8_t*>(p + 16);
    p += uint64_t{n} * 3 + 13;
    if (n < 2) {
      ++too_short;
      continue;
    }
    const size_t first = written;
    bool finite = true;
    for (uint32_t k = 0; k < n; ++k) {
      if (k > 0) {
        x += step[0];
        y += step[1];
        z += step[2];
        step += 3;
      }
      const auto fx = static_cast<double>(x), fy = static_cast<double>(y),
                 fz = static_cast<double>(z);
      // RAS to LPS: x and y negated.
      const glm::vec3 q(-(s[0][0] * fx + s[0][1] * fy + s[0][2] * fz + s[0][3]),
                        -(s[1][0] * fx + s[1][1] * fy + s[1][2] * fz + s[1][3]),
                        s[2][0] * fx + s[2][1] * fy + s[2][2] * fz + s[2][3]);
      finite = finite && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
      out.points[written++] = q;
    }
    if (!finite) {
      written = first;
      ++not_finite;
      continue;
    }
    out.offsets.push_back(static_cast<uint32_t>(written));
  }
  out.points.resize(written);
  if (too_short > 0)
    notes.push_back(fmt::format("{} streamlines of fewer than 2 points left out", too_short));
  if (not_finite > 0)
    notes.push_back(
        fmt::format("{} streamlines left out: trans_to_mni takes their points beyond finite floats",
                    not_finite));
  if (counts.streamlines == 0) notes.push_back("the file holds no streamlines");
  return out;
}

}  // namespace imx::detail
