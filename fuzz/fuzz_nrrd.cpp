// NRRD reader: an attached .nrrd, or (input holding the data marker) a detached .nhdr header
// with its data file "data.raw" beside it; then its header and a region of it (fuzz_region).
#include "harness.hpp"
#include "io/nrrd.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return imx::fuzz::fuzz_volume_reader(
      data, size, "in.nrrd", "in.nhdr",
      [](const auto& file) { return imx::detail::read_nrrd(file); },
      [](const auto& file) { return imx::detail::read_nrrd_header(file); },
      [](const auto& file, const imx::VoxelBox& box) {
        return imx::detail::read_nrrd_region(file, box);
      });
}
