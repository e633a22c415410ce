// NRRD reader: an attached .nrrd, or (input holding the data marker) a detached .nhdr header
// with its data file "data.raw" beside it; then its header and a region of it (fuzz_region).
// A 4-D file is read at its last frame, so that the frame strides (interleaved frames or
// stacked ones) are reached, not only frame 0.
#include <filesystem>

#include "harness.hpp"
#include "io/volume/nrrd.hpp"

namespace {

// The last frame the header declares (0 when it is refused); its labels must be one per frame
// or none, since the viewer and the CLI index them by frame.
int last_frame(const std::filesystem::path& file) {
  try {
    const imx::VolumeHeader h = imx::detail::read_nrrd_header(file);
    if (h.frames < 1 ||
        (!h.frame_labels.empty() && h.frame_labels.size() != static_cast<size_t>(h.frames))) {
      std::fprintf(stderr, "fuzz: %d frames with %zu labels\n", h.frames, h.frame_labels.size());
      __builtin_trap();
    }
    return h.frames - 1;
  } catch (const std::exception&) {
    return 0;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return imx::fuzz::fuzz_volume_reader(
      data, size, "in.nrrd", "in.nhdr",
      [](const auto& file) { return imx::detail::read_nrrd(file, last_frame(file)); },
      [](const auto& file) { return imx::detail::read_nrrd_header(file); },
      [](const auto& file, const imx::VoxelBox& box) {
        return imx::detail::read_nrrd_region(file, box, last_frame(file));
      });
}
