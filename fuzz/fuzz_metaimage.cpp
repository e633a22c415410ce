// MetaImage reader: an attached .mha, or (input holding the data marker) a detached .mhd header
// with its data file "data.raw" beside it; then its header and a region of it (fuzz_region).
#include "harness.hpp"
#include "io/volume/metaimage.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return imx::fuzz::fuzz_volume_reader(
      data, size, "in.mha", "in.mhd",
      [](const auto& file) { return imx::detail::read_metaimage(file); },
      [](const auto& file) { return imx::detail::read_metaimage_header(file); },
      [](const auto& file, const imx::VoxelBox& box) {
        return imx::detail::read_metaimage_region(file, box);
      });
}
