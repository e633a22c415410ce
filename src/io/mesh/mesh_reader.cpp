#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "core/limits.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "io/mesh/mesh_formats.hpp"
#include "io/mesh/mesh_space.hpp"
#include "io/mesh/vertex_normals.hpp"
#include "io/overlay/overlay_formats.hpp"
#include "io/streams/inflated_file.hpp"
#include "io/streams/regular_file.hpp"

namespace imx {

MeshFile read_mesh_file(const std::filesystem::path& file, const MeshReadOptions& options) {
  require_regular_file(file);
  if (!(options.crease_angle_deg >= 0.0 && options.crease_angle_deg <= 180.0))
    throw Error(fmt::format("{}: crease angle {:g} degrees is not in [0, 180]", file.string(),
                            options.crease_angle_deg));
  bool wrapped = false;
  const detail::FileProbe probe = detail::probe_file(file);
  const detail::MeshFormat* format = detail::find_mesh_format(probe, &wrapped);
  if (!format) {
    if (const detail::OverlayFormat* overlay = detail::find_overlay_format(probe))
      throw Error(
          fmt::format("{}: {} is a surface overlay ({}), not a mesh: give it after its "
                      "surface",
                      file.string(), file.filename().string(), overlay->info.name));
    throw Error(fmt::format("{}: '{}' is not a mesh format intermix reads (meshes: {})",
                            file.string(), detail::compound_suffix(file), mesh_formats()));
  }
  // x.obj.gz: the format's reader on an inflated copy, as large as the budget allows.
  detail::MeshContent content =
      wrapped ? detail::read_inflated(file, input_limits().max_memory, format->read)
              : format->read(file);
  MeshFile out;
  Mesh& mesh = out.mesh;
  MeshFileInfo& info = out.info;
  mesh = std::move(content.mesh);
  out.point_data = std::move(content.point_data);
  info.notes = std::move(content.notes);
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
  } else if (content.space) {
    info.space = *content.space;
    info.space_source = MeshSpaceSource::header;
  } else if (format->native_space != MeshSpace::lps) {
    info.space = format->native_space;  // GIfTI coordinates are NIfTI's; FreeSurfer's are RAS
    info.space_source = MeshSpaceSource::format;
  }
  if (info.space == MeshSpace::ras) detail::flip_ras_lps(mesh);

  if (mesh.colors.size() != mesh.positions.size()) mesh.colors.clear();
  info.file_colors = !mesh.colors.empty();
  info.file_normals = mesh.normals.size() == mesh.positions.size();
  info.file_vertices = mesh.positions.size();
  if (!info.file_normals) {
    try {
      detail::compute_vertex_normals(mesh, options.crease_angle_deg, &out.file_vertex);
    } catch (const OutOfMemory& e) {  // the budget's refusal names the mesh, not the file
      throw OutOfMemory(fmt::format("{}: {}", file.string(), e.what()));
    }
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
  return detail::find_mesh_format(detail::probe_file(file)) != nullptr;
}

std::string mesh_formats() {
  std::vector<const detail::FormatInfo*> rows;
  for (const detail::MeshFormat& format : detail::mesh_formats_table())
    rows.push_back(&format.info);
  return detail::list_formats(rows);
}

}  // namespace imx
