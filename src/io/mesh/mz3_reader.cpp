// Surfice MZ3 meshes and overlays (mz3.hpp): the header, the raw or inflated data, its sections.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/mesh/mz3.hpp"
#include "io/streams/byte_cursor.hpp"
#include "io/streams/file_head.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"

namespace imx::detail {
namespace {

constexpr uint16_t kMagic = 23117;  // "MZ" little-endian
constexpr size_t kHeaderBytes = 16;
constexpr uint16_t kFace = 1, kVert = 2, kRgba = 4, kScalar = 8, kDouble = 16, kAoMap = 32;
constexpr uint16_t kLastAttr = 63;  // larger ATTR values are future versions of the format
constexpr size_t kChunk = size_t{1} << 20;

struct Header {
  uint16_t attr = 0;
  uint32_t faces = 0, vertices = 0, skip = 0;

  bool has(uint16_t flag) const { return (attr & flag) != 0; }
  bool has_scalars() const { return has(kScalar) || has(kDouble); }
  uint64_t scalar_bytes() const { return has(kDouble) ? 8 : 4; }
  // Faces, vertices and colours: the data whose size the header gives.
  uint64_t fixed_bytes() const {
    return (has(kFace) ? uint64_t{12} * faces : 0) + (has(kVert) ? uint64_t{12} * vertices : 0) +
           (has(kRgba) ? uint64_t{4} * vertices : 0);
  }
};

// The header's fields, checked against the rules of the format's specification.
Header parse_header(std::string_view bytes, const std::string& what) {
  if (bytes.size() < kHeaderBytes)
    throw Error(
        fmt::format("{}: {} bytes is shorter than the 16-byte MZ3 header", what, bytes.size()));
  ByteCursor in(bytes, what, false);
  const auto magic = in.read<uint16_t>("the magic number");
  if (magic != kMagic)
    throw Error(fmt::format("{}: not an MZ3 file (magic {}, expected {} 'MZ', or gzip data)", what,
                            magic, kMagic));
  Header h;
  h.attr = in.read<uint16_t>("ATTR");
  h.faces = in.read<uint32_t>("NFACE");
  h.vertices = in.read<uint32_t>("NVERT");
  h.skip = in.read<uint32_t>("NSKIP");
  auto fail = [&](const std::string& why) {
    throw Error(fmt::format("{}: ATTR {}: {}", what, h.attr, why));
  };
  if (h.attr > kLastAttr) fail("over 63, a future version of MZ3 that intermix does not read");
  if (h.has(kFace) != h.has(kVert))
    fail(
        "isFACE and isVERT differ (faces need vertices, and vertices without faces are not a "
        "mesh)");
  if (h.has(kScalar) && h.has(kDouble)) fail("both isSCALAR and isDOUBLE (float32 or float64?)");
  if (!h.has(kVert) && !h.has(kRgba) && !h.has_scalars())
    fail("no vertices, colours or scalars: the file holds no data");
  if (h.has(kFace) && h.faces < 1)
    throw Error(fmt::format("{}: NFACE is 0, but isFACE says the file holds faces", what));
  if (h.vertices < 3)
    throw Error(
        fmt::format("{}: NVERT is {}, fewer than the 3 vertices of a triangle", what, h.vertices));
  return h;
}

// "N faces and M vertices with colours, after NSKIP S private bytes, (B bytes)": the data whose
// size the header gives, for messages.
std::string claim(const Header& h) {
  return fmt::format("{} faces and {} vertices{}{} ({} bytes)", h.has(kFace) ? h.faces : 0,
                     h.vertices, h.has(kRgba) ? " with colours" : "",
                     h.skip > 0 ? fmt::format(" after NSKIP {} private bytes", h.skip) : "",
                     h.fixed_bytes());
}

[[noreturn]] void surplus(const Header& h, const std::string& what, const std::string& bytes) {
  throw Error(
      fmt::format("{}: {} bytes follow the data the header claims (ATTR {} has no "
                  "scalars)",
                  what, bytes, h.attr));
}

// The header and the data after it and its NSKIP private bytes.
struct Contents {
  Header header;
  std::string data;
};

Contents read_raw(const std::filesystem::path& file, const std::string& what) {
  std::string bytes = read_file_bytes(file);
  Contents c;
  c.header = parse_header(bytes, what);
  const uint64_t start = kHeaderBytes + uint64_t{c.header.skip};
  if (start > bytes.size())
    throw Error(
        fmt::format("{}: NSKIP {} private bytes, but the file ends {} bytes after its "
                    "header",
                    what, c.header.skip, bytes.size() - kHeaderBytes));
  bytes.erase(0, static_cast<size_t>(start));
  c.data = std::move(bytes);
  return c;
}

// Inflated no further than the header's sizes allow: exactly its faces, vertices and colours,
// or, with scalars, layers up to the memory budget, which deflate's ratio to the compressed
// size also bounds.
Contents read_gzip(const std::filesystem::path& file, const std::string& what) {
  std::ifstream in = open_input_stream(file, what, std::ios::binary | std::ios::ate);
  const auto compressed = static_cast<uint64_t>(std::max<std::streamoff>(0, in.tellg()));
  in.seekg(0);
  GzipStream stream(in, what);
  std::string head(kHeaderBytes, '\0');
  head.resize(stream.read({reinterpret_cast<uint8_t*>(head.data()), head.size()}));
  Contents c;
  c.header = parse_header(head, what);
  const Header& h = c.header;
  const uint64_t needed = kHeaderBytes + h.skip + h.fixed_bytes();
  if (static_cast<double>(needed) > kMaxInflateRatio * static_cast<double>(compressed) + 4096.0)
    throw Error(fmt::format(
        "{}: the header claims {}, more than {} bytes of gzip data can inflate to (deflate "
        "expands at most about 1032:1)",
        what, claim(h), compressed));
  if (stream.skip(h.skip) < h.skip)
    throw Error(
        fmt::format("{}: NSKIP {} private bytes, but the data ends before them", what, h.skip));
  auto read_more = [&](uint64_t n) {
    check_memory(c.data.size() + n, fmt::format("{} (inflated)", what));
    const size_t at = c.data.size();
    c.data.resize(at + static_cast<size_t>(n));
    const size_t got =
        stream.read({reinterpret_cast<uint8_t*>(c.data.data()) + at, static_cast<size_t>(n)});
    c.data.resize(at + got);
    return got == n;
  };
  if (read_more(h.fixed_bytes()) && h.has_scalars()) {
    while (read_more(kChunk)) {
    }
  } else if (!h.has_scalars()) {
    // Counted, not kept: what follows the claimed data only makes the message.
    if (const size_t extra = stream.skip(kChunk + 1); extra > 0)
      surplus(h, what, extra > kChunk ? "over 1 MiB of" : std::to_string(extra));
  }
  stream.finish(c.data.size());  // its checksum, and a truncated stream said as such
  return c;
}

Contents read_contents(const std::filesystem::path& file) {
  const std::string what = file.string();
  const FileHead head = read_file_head(file, 2, what);
  return head.gzipped ? read_gzip(file, what) : read_raw(file, what);
}

// The data split into its sections, each checked against the bytes present.
struct Sections {
  std::string_view faces, vertices, rgba, scalars;
  uint64_t layers = 0;
};

Sections split(const Contents& c, const std::string& what) {
  const Header& h = c.header;
  const std::string_view data = c.data;
  if (h.fixed_bytes() > data.size())
    throw Error(fmt::format(
        "{}: the header claims {}, but the file holds {} bytes after its header{} (truncated, "
        "or a wrong count)",
        what, claim(h), data.size(), h.skip > 0 ? " and private bytes" : ""));
  Sections s;
  size_t at = 0;
  auto take = [&](bool present, uint64_t n) {
    if (!present) return std::string_view();
    const std::string_view part = data.substr(at, static_cast<size_t>(n));
    at += static_cast<size_t>(n);
    return part;
  };
  s.faces = take(h.has(kFace), uint64_t{12} * h.faces);
  s.vertices = take(h.has(kVert), uint64_t{12} * h.vertices);
  s.rgba = take(h.has(kRgba), uint64_t{4} * h.vertices);
  s.scalars = data.substr(at);
  const uint64_t layer_bytes = h.scalar_bytes() * h.vertices;
  if (!h.has_scalars()) {
    if (!s.scalars.empty())
      throw Error(
          fmt::format("{}: {} bytes follow the data the header claims (ATTR {} has no "
                      "scalars)",
                      what, s.scalars.size(), h.attr));
    return s;
  }
  if (s.scalars.empty() || s.scalars.size() % layer_bytes != 0)
    throw Error(
        fmt::format("{}: {} bytes of scalars are not whole layers of {} {} values (one per vertex)",
                    what, s.scalars.size(), h.vertices, h.has(kDouble) ? "float64" : "float32"));
  s.layers = s.scalars.size() / layer_bytes;
  return s;
}

// Layer `layer` of the scalars, as doubles.
std::vector<double> scalar_layer(const Sections& s, const Header& h, uint64_t layer,
                                 const std::string& what) {
  const uint64_t n = h.vertices;
  ByteCursor in(s.scalars.substr(static_cast<size_t>(layer * n * h.scalar_bytes())), what, false);
  std::vector<double> values(static_cast<size_t>(n));
  for (double& v : values)
    v = h.has(kDouble) ? in.read<double>("a scalar") : in.read<float>("a scalar");
  return values;
}

std::string layer_name(const Header& h, uint64_t layer) {
  if (h.has(kAoMap)) {
    if (layer == 0) return "ambient_occlusion";
    --layer;
  }
  return layer == 0 ? "scalars" : fmt::format("scalars{}", layer);
}

// A template's scalars are region numbers and its colours theirs (Surfice): one label each.
void make_label_table(VertexOverlay& out, std::string_view rgba, const std::string& what) {
  std::map<int64_t, size_t> first_vertex;  // region -> the vertex that gave its colour
  auto colour = [&](size_t v) {
    return fmt::format("({}, {}, {}, {})", static_cast<uint8_t>(rgba[4 * v]),
                       static_cast<uint8_t>(rgba[4 * v + 1]), static_cast<uint8_t>(rgba[4 * v + 2]),
                       static_cast<uint8_t>(rgba[4 * v + 3]));
  };
  for (size_t v = 0; v < out.values.size(); ++v) {
    const double value = out.values[v];
    if (std::isnan(value)) continue;  // a vertex in no region
    if (!(std::abs(value) < 9.0e15) || value != std::round(value))
      throw Error(fmt::format(
          "{}: vertex {} has region number {:g}, not an integer (a file with colours and "
          "scalars is a template: its scalars number regions)",
          what, v, value));
    const auto key = static_cast<int64_t>(value);
    auto [it, added] = first_vertex.emplace(key, v);
    if (!added && rgba.substr(4 * it->second, 4) != rgba.substr(4 * v, 4))
      throw Error(fmt::format(
          "{}: region {} has two colours, {} at vertex {} and {} at vertex {} (a template "
          "gives each region one)",
          what, key, colour(it->second), it->second, colour(v), v));
  }
  out.labels = true;
  for (const auto& [key, v] : first_vertex) {
    OverlayLabel l;
    l.key = key;
    l.name = std::to_string(key);
    for (int c = 0; c < 4; ++c)
      l.rgba[c] =
          static_cast<float>(static_cast<uint8_t>(rgba[4 * v + static_cast<size_t>(c)])) / 255.0f;
    out.table.push_back(std::move(l));
  }
}

}  // namespace

PolyDataFile read_mz3_mesh(const std::filesystem::path& file) {
  const std::string what = file.string();
  const Contents c = read_contents(file);
  const Header& h = c.header;
  if (!h.has(kFace))
    throw Error(fmt::format(
        "{}: an MZ3 file of per-vertex {} without faces or vertices: an overlay, to be shown "
        "on the surface it belongs to",
        what, h.has_scalars() ? "values" : "colours"));
  const Sections s = split(c, what);
  const uint64_t n = h.vertices;
  // Positions, triangles, colours (12 bytes each a vertex or face) and the layers as doubles.
  check_memory(
      c.data.size() + 12 * (2 * n + uint64_t{h.faces}) + 8 * n * s.layers,
      fmt::format("{}: {} vertices, {} faces and {} scalar layers", what, n, h.faces, s.layers));
  PolyDataFile out;
  out.space = MeshSpace::ras;
  Mesh& mesh = out.mesh;
  ByteCursor vertices(s.vertices, what, false);
  mesh.positions.resize(static_cast<size_t>(n));
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    glm::vec3& p = mesh.positions[v];
    for (int k = 0; k < 3; ++k) p[k] = vertices.read<float>("a vertex");
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw Error(fmt::format("{}: vertex {} at ({:g}, {:g}, {:g}) has a non-finite coordinate",
                              what, v, p.x, p.y, p.z));
  }
  ByteCursor faces(s.faces, what, false);
  mesh.triangles.resize(h.faces);
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const auto index = faces.read<int32_t>("a face");
      if (index < 0 || static_cast<uint64_t>(index) >= n)
        throw Error(fmt::format("{}: face {} uses vertex {}, but the file has {} vertices", what, f,
                                index, n));
      mesh.triangles[f][k] = static_cast<uint32_t>(index);
    }
  }
  if (h.has(kRgba)) {
    mesh.colors.resize(static_cast<size_t>(n));
    const auto byte = [&](size_t v, size_t k) {
      return static_cast<float>(static_cast<uint8_t>(s.rgba[4 * v + k])) / 255.0f;
    };
    for (size_t v = 0; v < mesh.colors.size(); ++v)
      mesh.colors[v] = display_to_linear(glm::vec3(byte(v, 0), byte(v, 1), byte(v, 2)));
  }
  for (uint64_t layer = 0; layer < s.layers; ++layer)
    out.point_data.push_back({layer_name(h, layer), 1, scalar_layer(s, h, layer, what)});
  return out;
}

VertexOverlay read_mz3_overlay(const std::filesystem::path& file, int layer) {
  const std::string what = file.string();
  if (layer < -1)
    throw Error(
        fmt::format("{}: scalar layer {} does not exist (layers count from 0)", what, layer));
  const Contents c = read_contents(file);
  const Header& h = c.header;
  if (!h.has_scalars())
    throw Error(
        fmt::format("{}: the MZ3 file holds no scalars (ATTR {}){}", what, h.attr,
                    h.has(kRgba) ? ", only colours: intermix reads overlays of values" : ""));
  const Sections s = split(c, what);
  uint64_t index = layer >= 0 ? static_cast<uint64_t>(layer) : 0;
  if (layer < 0 && h.has(kAoMap) && s.layers > 1) index = 1;  // past the shading map
  if (index >= s.layers)
    throw Error(
        fmt::format("{}: has {} scalar layers: there is no layer {}", what, s.layers, index));
  check_memory(c.data.size() + 8 * uint64_t{h.vertices}, what);
  VertexOverlay out;
  out.claimed_vertices = h.vertices;
  out.values = scalar_layer(s, h, index, what);
  if (h.has(kRgba)) make_label_table(out, s.rgba, what);
  return out;
}

bool mz3_is_overlay(const std::filesystem::path& file) {
  const std::string what = file.string();
  require_regular_file(file);
  return !parse_header(read_file_head(file, kHeaderBytes, what).bytes, what).has(kFace);
}

}  // namespace imx::detail
