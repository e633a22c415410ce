// FreeSurfer MGH reader: the input is an .mgh file (gzip data, an .mgz, is found by its magic).
// The last frame is read, so that the skips past the others are reached; then its header (with
// the footer's TR) and a region of that frame (fuzz_region).
#include <exception>

#include "harness.hpp"
#include "io/volume/mgh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const std::filesystem::path file = dir.write("in.mgh", data, size);
  int frame = 0;
  try {
    frame = imx::detail::read_mgh_header(file).frames - 1;
  } catch (const std::exception& e) {
    refused(e);
  }
  try {
    // The reader only: validate() and range() would double the time of large volumes.
    check_volume(imx::detail::read_mgh(file, frame));
    accepted("volume");
  } catch (const std::exception& e) {
    refused(e);
  }
  fuzz_region(
      file, size > 0 ? data[size - 1] : 0,
      [](const auto& f) { return imx::detail::read_mgh_header(f); },
      [frame](const auto& f, const imx::VoxelBox& box) {
        return imx::detail::read_mgh_region(f, box, frame);
      });
  return 0;
}
