// Surfice MZ3 reader (io/mesh/mz3.hpp): the input is an .mz3 file, raw or gzip (found by its
// magic). It goes through the header probe, the mesh read (its faces must name its vertices,
// its colours and each scalar layer one per vertex) and the overlay read of its first and
// second layers (one value per claimed vertex; a template's table must hold every region).
#include <cmath>
#include <exception>
#include <set>

#include "harness.hpp"
#include "io/mesh/mz3.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const std::filesystem::path file = dir.write("in.mz3", data, size);
  try {
    imx::detail::mz3_is_overlay(file);
  } catch (const std::exception& e) {
    refused(e);
  }
  try {
    const imx::detail::PolyDataFile m = imx::detail::read_mz3_mesh(file);
    check_mesh(m.mesh);
    for (const imx::MeshPointData& d : m.point_data)
      if (d.components != 1 || d.values.size() != m.mesh.positions.size()) __builtin_trap();
    accepted("mesh");
  } catch (const std::exception& e) {
    refused(e);
  }
  for (int layer : {-1, 1}) {
    try {
      const imx::detail::VertexOverlay o = imx::detail::read_mz3_overlay(file, layer);
      if (o.values.size() != o.claimed_vertices) __builtin_trap();
      if (o.labels) {
        std::set<double> keys;
        for (const imx::detail::OverlayLabel& l : o.table) keys.insert(static_cast<double>(l.key));
        for (double v : o.values)
          if (!std::isnan(v) && keys.count(v) == 0) __builtin_trap();
      }
      accepted("overlay");
    } catch (const std::exception& e) {
      refused(e);
    }
  }
  return 0;
}
