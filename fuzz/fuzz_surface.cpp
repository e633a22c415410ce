// The surface and per-vertex overlay readers of values on meshes: the first byte picks the
// format (kFormats), the rest is the file. FreeSurfer triangle surfaces, VTK legacy .vtk and XML
// .vtp go through read_mesh_file (point data and the file-vertex map included), FreeSurfer
// curvature, .annot and .label files through read_vertex_overlay and overlay_values. New
// formats go at the end: a seed's first byte keeps its meaning.
#include <cmath>
#include <exception>
#include <iterator>

#include "harness.hpp"
#include "intermix/io.hpp"
#include "io/overlay/vertex_overlay.hpp"

namespace {

struct Format {
  const char* name;  // the file's name: it decides the reader, as a user's would
  bool mesh;
};
constexpr Format kFormats[] = {{"lh.pial", true},         {"in.vtk", true},
                               {"in.vtp", true},          {"lh.thickness", false},
                               {"lh.aparc.annot", false}, {"lh.BA1.label", false}};

void check_mesh_file(const imx::MeshFile& m) {
  imx::fuzz::check_mesh(m.mesh);
  if (m.file_vertex.size() != m.mesh.positions.size()) __builtin_trap();
  for (uint32_t f : m.file_vertex)
    if (f >= m.info.file_vertices) __builtin_trap();
  for (const imx::MeshPointData& d : m.point_data)
    if (d.components < 1 || d.values.size() != m.info.file_vertices * d.components)
      __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  if (size < 1) return 0;
  const ScratchDir& dir = scratch();
  dir.clear();
  const Format& format = kFormats[data[0] % std::size(kFormats)];
  std::filesystem::path file = dir.write(format.name, data + 1, size - 1);
  try {
    if (format.mesh) {
      check_mesh_file(imx::read_mesh_file(file));
    } else {
      const imx::detail::VertexOverlay o = imx::detail::read_vertex_overlay(file);
      const size_t n = o.claimed_vertices > 0 ? o.claimed_vertices : 1000;
      const std::vector<double> values = imx::detail::overlay_values(o, n, file.string());
      if (values.size() != n) __builtin_trap();
    }
    accepted(format.name);
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
