#include "io/mesh/freesurfer_surface.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/byte_cursor.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {
namespace {

constexpr size_t kMaxStampBytes = 4096;  // the "created by" line
constexpr size_t kMaxFooterLine = 4096;

bool has_magic(std::string_view head, uint8_t last) {
  return head.size() >= 3 && static_cast<uint8_t>(head[0]) == 0xFF &&
         static_cast<uint8_t>(head[1]) == 0xFF && static_cast<uint8_t>(head[2]) == last;
}

// The volume geometry FreeSurfer stores after the faces (VOL_GEOM).
struct VolumeGeometry {
  bool valid = false;
  std::array<double, 3> volume{}, voxelsize{}, xras{}, yras{}, zras{}, cras{};
};

std::array<double, 3> numbers3(std::string_view value, const ByteCursor& at, std::string_view key) {
  const auto words = split_words(value);
  std::array<double, 3> out{};
  for (size_t i = 0; i < 3; ++i) {
    std::optional<double> v =
        i < words.size() ? parse_header_number<double>(words[i]) : std::nullopt;
    if (words.size() != 3 || !v || !std::isfinite(*v))
      throw Error(fmt::format("{}: volume geometry '{}' is '{}', not three numbers", at.what(), key,
                              shown(value)));
    out[i] = *v;
  }
  return out;
}

// The footer, as nibabel's read_geometry(read_metadata=True) reads it: nothing (or an unknown
// tag) is no geometry; a known tag followed by lines that are not the geometry is an error.
std::optional<VolumeGeometry> read_footer(ByteCursor& in) {
  if (in.remaining() < 4) return std::nullopt;
  const int32_t first = in.read<int32_t>("the footer's tag");
  if (first != 20) {
    if (in.remaining() < 8) return std::nullopt;
    const int32_t second = in.read<int32_t>("the footer's tag");
    const int32_t third = in.read<int32_t>("the footer's tag");
    if (!(first == 2 && second == 0 && third == 20)) return std::nullopt;  // not a geometry
  }
  VolumeGeometry g;
  for (const char* key :
       {"valid", "filename", "volume", "voxelsize", "xras", "yras", "zras", "cras"}) {
    const std::string_view text =
        in.line(fmt::format("volume geometry line '{}'", key), kMaxFooterLine);
    const size_t eq = text.find('=');
    if (eq == std::string_view::npos || trim(text.substr(0, eq)) != key ||
        text.find('=', eq + 1) != std::string_view::npos)
      throw Error(fmt::format("{}: volume geometry line '{}' is not '{} = ...'", in.what(),
                              shown(text), key));
    std::string_view value = trim(text.substr(eq + 1));
    const std::string_view k(key);
    if (k == "valid")
      g.valid = value.starts_with("1");
    else if (k == "volume")
      g.volume = numbers3(value, in, k);
    else if (k == "voxelsize")
      g.voxelsize = numbers3(value, in, k);
    else if (k == "xras")
      g.xras = numbers3(value, in, k);
    else if (k == "yras")
      g.yras = numbers3(value, in, k);
    else if (k == "zras")
      g.zras = numbers3(value, in, k);
    else if (k == "cras")
      g.cras = numbers3(value, in, k);
  }
  return g;
}

// tkr-RAS -> scanner RAS: vox2ras * inverse(tkr vox2ras), FreeSurfer's (and nibabel's MGHHeader)
// definitions. Both map the grid's centre (index dims / 2) to their origin, c_ras in scanner
// RAS and 0 in tkr-RAS, so the map is M * inverse(Mtkr) + c_ras.
glm::dmat4 tkr_to_scanner(const VolumeGeometry& g, const std::string& what) {
  const glm::dvec3 size(g.voxelsize[0], g.voxelsize[1], g.voxelsize[2]);
  if (!(size.x > 0.0 && size.y > 0.0 && size.z > 0.0))
    throw Error(fmt::format("{}: volume geometry voxelsize {} {} {} is not positive", what, size.x,
                            size.y, size.z));
  glm::dmat3 m;  // columns: the direction cosines times the voxel sizes
  m[0] = glm::dvec3(g.xras[0], g.xras[1], g.xras[2]) * size.x;
  m[1] = glm::dvec3(g.yras[0], g.yras[1], g.yras[2]) * size.y;
  m[2] = glm::dvec3(g.zras[0], g.zras[1], g.zras[2]) * size.z;
  glm::dmat3 tkr(0.0);
  tkr[0][0] = -size.x;
  tkr[2][1] = size.z;
  tkr[1][2] = -size.y;
  const glm::dmat3 r = m * glm::inverse(tkr);
  // The cosines must be orthonormal for the map to be a rotation: else the geometry is damaged.
  const glm::dmat3 rtr = glm::transpose(r) * r;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k)
      if (!(std::abs(rtr[c][k] - (c == k ? 1.0 : 0.0)) < 1e-3))
        throw Error(
            fmt::format("{}: volume geometry's xras, yras, zras are not orthonormal "
                        "direction cosines",
                        what));
  glm::dmat4 out(r);
  out[3] = glm::dvec4(g.cras[0], g.cras[1], g.cras[2], 1.0);
  return out;
}

}  // namespace

bool is_freesurfer_surface(std::string_view head) {
  return has_magic(head, 0xFE);
}

FreeSurferSurface read_freesurfer_surface(const std::filesystem::path& file) {
  const std::string what = file.string();
  const std::string bytes = read_file_bytes(file);
  ByteCursor in(bytes, what, true);
  const std::string_view magic = in.take(3, "the magic number");
  if (has_magic(magic, 0xFF) || has_magic(magic, 0xFD))
    throw Error(
        fmt::format("{}: a FreeSurfer quad surface (or a curvature file): intermix reads "
                    "only triangle surfaces (magic 0xFFFFFE)",
                    what));
  if (!has_magic(magic, 0xFE))
    throw Error(fmt::format("{}: not a FreeSurfer triangle surface (no magic 0xFFFFFE)", what));
  in.line("the 'created by' line", kMaxStampBytes);
  in.line("the line after 'created by'", kMaxStampBytes);
  const int32_t vnum = in.read<int32_t>("the vertex count");
  const int32_t fnum = in.read<int32_t>("the face count");
  if (vnum <= 0 || fnum < 0)
    throw Error(fmt::format("{}: {} vertices and {} faces is not a surface", what, vnum, fnum));
  in.need(uint64_t{12} * static_cast<uint64_t>(vnum) + uint64_t{12} * static_cast<uint64_t>(fnum),
          fmt::format("{} vertices and {} faces", vnum, fnum));
  check_memory(uint64_t{12} * static_cast<uint64_t>(vnum) * 3 + uint64_t{12} * fnum, what);
  FreeSurferSurface out;
  Mesh& mesh = out.mesh;
  mesh.positions.resize(static_cast<size_t>(vnum));
  for (glm::vec3& p : mesh.positions)
    for (int c = 0; c < 3; ++c) p[c] = in.read<float>("a vertex");
  mesh.triangles.resize(static_cast<size_t>(fnum));
  for (size_t f = 0; f < mesh.triangles.size(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int32_t v = in.read<int32_t>("a face");
      if (v < 0 || v >= vnum)
        throw Error(fmt::format("{}: face {} uses vertex {}, but the file has {} vertices", what, f,
                                v, vnum));
      mesh.triangles[f][c] = static_cast<uint32_t>(v);
    }
  const std::string shown_name = file.filename().string();
  const std::optional<VolumeGeometry> geometry = read_footer(in);
  if (!geometry || !geometry->valid) {
    out.note = fmt::format(
        "{}: FreeSurfer surface without {}volume geometry: its tkr-RAS is taken "
        "as scanner RAS (c_ras unknown)",
        shown_name, geometry ? "a valid " : "");
    return out;
  }
  const glm::dmat4 m = tkr_to_scanner(*geometry, what);
  for (glm::vec3& p : mesh.positions) {
    const glm::dvec4 q = m * glm::dvec4(glm::dvec3(p), 1.0);
    p = glm::vec3(q);
  }
  out.note = fmt::format(
      "{}: FreeSurfer surface in tkr-RAS, moved to scanner RAS by its volume "
      "geometry (c_ras {:g} {:g} {:g})",
      shown_name, geometry->cras[0], geometry->cras[1], geometry->cras[2]);
  return out;
}

}  // namespace imx::detail
