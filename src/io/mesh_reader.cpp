#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/glm.hpp>

#include "core/limits.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/freesurfer_surface.hpp"
#include "io/gifti_reader.hpp"
#include "io/gltf_check.hpp"
#include "io/header_text.hpp"
#include "io/mesh_assimp_plugin.hpp"
#include "io/mesh_space.hpp"
#include "io/ply_reader.hpp"
#include "io/polydata.hpp"
#include "io/polygon_check.hpp"
#include "io/regular_file.hpp"
#include "io/vertex_normals.hpp"

namespace imx {
namespace {

// PLY by extension or by its first line, whatever the extension says.
bool is_ply(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".ply") return true;
  char head[5] = {};
  std::ifstream(file, std::ios::binary).read(head, sizeof head);
  return std::memcmp(head, "ply", 3) == 0 && (head[3] == '\n' || head[3] == '\r');
}

// The first bytes of a file (fewer when it is shorter).
std::string file_head(const std::filesystem::path& file, size_t n) {
  std::string head(n, '\0');
  std::ifstream in(file, std::ios::binary);
  in.read(head.data(), static_cast<std::streamsize>(n));
  head.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return head;
}

// FreeSurfer's surface names: lh.pial and the like have these as "extensions".
constexpr const char* kFreeSurferSurfaces[] = {".pial",     ".white",  ".inflated",    ".orig",
                                               ".smoothwm", ".sphere", ".midthickness"};

// The formats assimp reads for intermix, by extension (others are refused rather than handed
// to one of assimp's forty importers).
constexpr const char* kAssimpFormats[] = {".obj", ".stl", ".off", ".gltf", ".glb"};

Mesh read_with_assimp(const std::filesystem::path& file, const std::string& ext) {
  if (std::find(std::begin(kAssimpFormats), std::end(kAssimpFormats), ext) ==
      std::end(kAssimpFormats))
    throw Error(fmt::format("{}: '{}' is not a mesh format intermix reads (it reads {})",
                            file.string(), ext, mesh_formats()));
  if (ext == ".gltf" || ext == ".glb") detail::check_gltf(file);
  if (ext == ".obj") detail::check_obj_polygons(file);
  if (ext == ".off") detail::check_off(file);
  // assimp is a plugin, loaded by the first such file (io/mesh_assimp_plugin.hpp).
  // glTF stores linear colours; OBJ (and STL) colours are display values, sRGB-encoded.
  Mesh mesh = detail::import_mesh_with_plugin(file, ext != ".gltf" && ext != ".glb");
  // STL's normals are per facet: as vertex normals they would keep every STL faceted.
  if (ext == ".stl") mesh.normals.clear();
  return mesh;
}

}  // namespace

MeshFile read_mesh_file(const std::filesystem::path& file, const MeshReadOptions& options) {
  require_regular_file(file);
  if (!(options.crease_angle_deg >= 0.0 && options.crease_angle_deg <= 180.0))
    throw Error(fmt::format("{}: crease angle {:g} degrees is not in [0, 180]", file.string(),
                            options.crease_angle_deg));
  // Debian 12's assimp hangs or crashes on some malformed PLY files: those are read here.
  const bool ply = is_ply(file);
  const std::string ext = ply ? ".ply" : detail::lower(file.extension().string());
  MeshFile out;
  Mesh& mesh = out.mesh;
  MeshFileInfo& info = out.info;
  std::optional<MeshSpace> file_space;  // what the file's own header says
  std::string head = ply ? std::string() : file_head(file, 3);
  const bool freesurfer = detail::is_freesurfer_surface(head);
  if (!freesurfer && head.size() == 3 && static_cast<uint8_t>(head[0]) == 0xFF &&
      static_cast<uint8_t>(head[1]) == 0xFF &&
      (static_cast<uint8_t>(head[2]) == 0xFF || static_cast<uint8_t>(head[2]) == 0xFD))
    throw Error(
        fmt::format("{}: a FreeSurfer quad surface or curvature file (magic 0xFFFFFF or "
                    "0xFFFFFD): intermix reads triangle surfaces (0xFFFFFE) as meshes; "
                    "a curvature file is an overlay",
                    file.string()));
  if (ply) {
    mesh = detail::read_ply(file);
  } else if (freesurfer) {
    detail::FreeSurferSurface surface = detail::read_freesurfer_surface(file);
    mesh = std::move(surface.mesh);
    info.notes.push_back(std::move(surface.note));
  } else if (ext == ".gii") {
    mesh = detail::read_gifti(file);
  } else if (ext == ".vtk" || ext == ".vtp") {
    detail::PolyDataFile poly =
        ext == ".vtk" ? detail::read_vtk_legacy(file) : detail::read_vtp(file);
    mesh = std::move(poly.mesh);
    out.point_data = std::move(poly.point_data);
    file_space = poly.space;
  } else {
    mesh = read_with_assimp(file, ext);
  }
  if (mesh.triangles.empty())
    throw Error(fmt::format("{}: the file holds no triangles", file.string()));
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3& p = mesh.positions[i];
    if (!(std::abs(p.x) <= kMaxCoordinateMm && std::abs(p.y) <= kMaxCoordinateMm &&
          std::abs(p.z) <= kMaxCoordinateMm))
      throw Error(
          fmt::format("{}: vertex {} at ({:g}, {:g}, {:g}) is not a finite position within "
                      "{:g} mm of the origin",
                      file.string(), i, p.x, p.y, p.z, kMaxCoordinateMm));
  }
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const glm::uvec3& t = mesh.triangles[f];
    if (std::max({t.x, t.y, t.z}) >= mesh.positions.size())
      throw Error(fmt::format("{}: triangle {} uses vertex {}, but the file has {} vertices",
                              file.string(), f, std::max({t.x, t.y, t.z}), mesh.positions.size()));
  }

  if (options.space) {
    info.space = *options.space;
    info.space_source = MeshSpaceSource::option;
  } else if (auto header = file_space ? file_space : detail::header_space(file, ext)) {
    info.space = *header;
    info.space_source = MeshSpaceSource::header;
  } else if (ext == ".gii" || freesurfer) {
    info.space = MeshSpace::ras;  // GIfTI coordinates are NIfTI's; FreeSurfer's are RAS
    info.space_source = MeshSpaceSource::format;
  }
  if (info.space == MeshSpace::ras) detail::flip_ras_lps(mesh);

  if (mesh.colors.size() != mesh.positions.size()) mesh.colors.clear();
  info.file_colors = !mesh.colors.empty();
  info.file_normals = mesh.normals.size() == mesh.positions.size();
  info.file_vertices = mesh.positions.size();
  if (!info.file_normals) {
    detail::compute_vertex_normals(mesh, options.crease_angle_deg, &out.file_vertex);
  } else {
    out.file_vertex.resize(mesh.positions.size());
    for (size_t i = 0; i < out.file_vertex.size(); ++i)
      out.file_vertex[i] = static_cast<uint32_t>(i);
  }
  return out;
}

Mesh read_mesh(const std::filesystem::path& file) {
  return read_mesh_file(file).mesh;
}

bool is_mesh_file(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".ply" || ext == ".gii" || ext == ".vtk" || ext == ".vtp" ||
         std::find(std::begin(kAssimpFormats), std::end(kAssimpFormats), ext) !=
             std::end(kAssimpFormats) ||
         std::find(std::begin(kFreeSurferSurfaces), std::end(kFreeSurferSurfaces), ext) !=
             std::end(kFreeSurferSurfaces);
}

std::string mesh_formats() {
  return fmt::format(".ply, .gii, .vtk, .vtp, {}, FreeSurfer surfaces (lh.pial, ...)",
                     fmt::join(kAssimpFormats, ", "));
}

}  // namespace imx
