// One row per mesh format. A new format: its reader file and one row here (docs/architecture.md).
#include "io/mesh/mesh_formats.hpp"

#include <vector>

#include "io/mesh/freesurfer_surface.hpp"
#include "io/mesh/gifti_reader.hpp"
#include "io/mesh/gltf_check.hpp"
#include "io/mesh/mesh_assimp_plugin.hpp"
#include "io/mesh/mesh_space.hpp"
#include "io/mesh/mz3.hpp"
#include "io/mesh/ply_reader.hpp"
#include "io/mesh/polydata.hpp"
#include "io/mesh/polygon_check.hpp"
#include "io/mesh/stl_check.hpp"

namespace imx::detail {
namespace {

bool ply_head(const FileProbe& probe) {
  return probe.head.starts_with("ply\n") || probe.head.starts_with("ply\r");
}

// Surfice's MZ3 (raw or gzip: the probe's bytes are inflated) with faces: a mesh.
bool mz3_mesh_head(const FileProbe& probe) {
  return probe.head.size() >= 4 && probe.head.starts_with("MZ") &&
         (static_cast<uint8_t>(probe.head[2]) & 1) != 0;
}

bool freesurfer_head(const FileProbe& probe) {
  return is_freesurfer_surface(probe.head);
}

MeshContent ply(const std::filesystem::path& file) {
  return {read_ply(file), {}, header_space(file, ".ply"), {}};
}

MeshContent freesurfer(const std::filesystem::path& file) {
  FreeSurferSurface surface = read_freesurfer_surface(file);
  return {std::move(surface.mesh), {}, std::nullopt, {std::move(surface.note)}};
}

MeshContent gifti(const std::filesystem::path& file) {
  std::vector<std::string> notes;
  Mesh mesh = read_gifti(file, &notes);
  return {std::move(mesh), {}, std::nullopt, std::move(notes)};
}

MeshContent polydata(PolyDataFile poly) {
  return {std::move(poly.mesh), std::move(poly.point_data), poly.space, {}};
}

MeshContent mz3(const std::filesystem::path& file) {
  return polydata(read_mz3_mesh(file));
}

MeshContent vtk_legacy(const std::filesystem::path& file) {
  return polydata(read_vtk_legacy(file));
}

MeshContent vtp(const std::filesystem::path& file) {
  return polydata(read_vtp(file));
}

// assimp is a plugin, loaded by the first such file (io/mesh/mesh_assimp_plugin.hpp), and reads
// only after intermix's own checks of the file. OBJ and STL colours are display values
// (sRGB-encoded); glTF stores linear ones.
MeshContent obj(const std::filesystem::path& file) {
  check_obj_polygons(file);
  return {import_mesh_with_plugin(file, true), {}, header_space(file, ".obj"), {}};
}

MeshContent stl(const std::filesystem::path& file) {
  check_stl(file);
  Mesh mesh = import_mesh_with_plugin(file, true);
  mesh.normals.clear();  // STL's normals are per facet: as vertex normals they keep it faceted
  return {std::move(mesh), {}, header_space(file, ".stl"), {}};
}

MeshContent off(const std::filesystem::path& file) {
  check_off(file);
  return {import_mesh_with_plugin(file, true), {}, std::nullopt, {}};
}

MeshContent gltf(const std::filesystem::path& file) {
  check_gltf(file);
  return {import_mesh_with_plugin(file, false), {}, std::nullopt, {}};
}

}  // namespace

std::span<const MeshFormat> mesh_formats_table() {
  // Debian 12's assimp hangs or crashes on some malformed PLY files: PLY is read by intermix,
  // known by its first line whatever the extension.
  static const std::vector<MeshFormat> table = {
      {{.kind = FileKind::mesh,
        .name = "PLY",
        .extensions = {".ply"},
        .sniff = ply_head,
        .fuzz_target = "fuzz_ply",
        .fuzz_seeds = "*.ply",
        .reference = "assimp, VTK",
        .gz_wrapped = {".ply"}},
       ply,
       MeshSpace::lps},
      {{.kind = FileKind::mesh,
        .name = "FreeSurfer surface",
        .extensions = {".pial", ".white", ".inflated", ".orig", ".smoothwm", ".sphere",
                       ".midthickness"},
        .sniff = freesurfer_head,
        .fuzz_target = "fuzz_surface",
        .reference = "nibabel.freesurfer.read_geometry"},
       freesurfer,
       MeshSpace::ras},
      {{.kind = FileKind::mesh,
        .name = "GIfTI surface",
        .extensions = {".gii", ".surf.gii"},
        .fuzz_target = "fuzz_mesh",
        .reference = "nibabel"},
       gifti,
       MeshSpace::ras},
      {{.kind = FileKind::mesh,
        .name = "VTK legacy polydata",
        .extensions = {".vtk"},
        .fuzz_target = "fuzz_surface",
        .reference = "VTK (vtkPolyDataReader)",
        .gz_wrapped = {".vtk"}},
       vtk_legacy,
       MeshSpace::lps},
      {{.kind = FileKind::mesh,
        .name = "VTK XML polydata",
        .extensions = {".vtp"},
        .fuzz_target = "fuzz_surface",
        .reference = "VTK (vtkXMLPolyDataReader)"},
       vtp,
       MeshSpace::lps},
      {{.kind = FileKind::mesh,
        .name = "Wavefront OBJ",
        .extensions = {".obj"},
        .fuzz_target = "fuzz_mesh",
        .fuzz_seeds = "*.obj",
        .reference = "assimp",
        .gz_wrapped = {".obj"}},
       obj,
       MeshSpace::lps},
      {{.kind = FileKind::mesh,
        .name = "STL",
        .extensions = {".stl"},
        .fuzz_target = "fuzz_mesh",
        .fuzz_seeds = "*.stl",
        .reference = "assimp",
        .gz_wrapped = {".stl"}},
       stl,
       MeshSpace::lps},
      {{.kind = FileKind::mesh,
        .name = "OFF",
        .extensions = {".off"},
        .fuzz_target = "fuzz_mesh",
        .fuzz_seeds = "*.off",
        .reference = "assimp",
        .gz_wrapped = {".off"}},
       off,
       MeshSpace::lps},
      {{.kind = FileKind::mesh,
        .name = "glTF 2",
        .extensions = {".gltf", ".glb"},
        .fuzz_target = "fuzz_mesh",
        .fuzz_seeds = "*.gltf *.glb",
        .reference = "assimp",
        .gz_wrapped = {".glb"}},
       gltf,
       MeshSpace::lps},
      {{.kind = FileKind::mesh,
        .name = "Surfice/NiiVue MZ3",
        .extensions = {".mz3"},
        .sniff = mz3_mesh_head,
        .fuzz_target = "fuzz_mz3",
        .fuzz_seeds = "*.mz3",
        .reference = "NiiVue (readMZ3), Surfice"},
       mz3,
       MeshSpace::ras},
  };
  return table;
}

const MeshFormat* find_mesh_format(const FileProbe& probe, bool* wrapped) {
  return find_format(mesh_formats_table(), probe, wrapped);
}

}  // namespace imx::detail
