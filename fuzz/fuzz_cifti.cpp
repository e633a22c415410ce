// CIFTI-2 reader: the input is a .dscalar.nii (a NIfTI-2 header, its XML extension and the data
// matrix). Every surface structure's last map is read onto its vertices, and the structure a
// surface named after the left hemisphere would be is chosen.
#include <exception>

#include "harness.hpp"
#include "io/overlay/cifti.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const std::filesystem::path file = dir.write("in.dscalar.nii", data, size);
  (void)imx::detail::is_cifti(file);
  try {
    const imx::detail::CiftiFile c = imx::detail::read_cifti(file);
    for (const imx::detail::CiftiBrainModel& m : c.models) {
      if (!m.surface) continue;
      const imx::detail::VertexOverlay o =
          imx::detail::cifti_overlay(c, m.structure, c.maps - 1, file.string());
      if (o.values.size() != static_cast<size_t>(m.surface_vertices)) std::abort();
    }
    try {
      (void)imx::detail::cifti_structure_of_surface(c, dir.path() / "lh.white", 32492);
    } catch (const std::exception& e) {
      refused(e);
    }
    accepted("cifti");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
