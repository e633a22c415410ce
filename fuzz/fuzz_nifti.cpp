// NIfTI-1/NIfTI-2/Analyze reader: a single file (.nii; gzip data is found by its magic, whatever
// the name), or (input holding the data marker) a .hdr header with its voxels "in.img" beside it,
// so that pairs and Analyze headers are fuzzed too. The last frame is read, so that a 4-D
// header's skips past the other frames are reached; then its header and a region of that frame
// (fuzz_region).
#include <exception>

#include "harness.hpp"
#include "intermix/io.hpp"
#include "io/volume/nifti.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const Split parts = split_at(as_view(data, size), kDataMarker);
  std::filesystem::path file;
  if (parts.found) {
    file = dir.write("in.hdr", parts.head);
    dir.write("in.img", parts.tail);
  } else {
    const bool gz = size >= 2 && data[0] == 0x1f && data[1] == 0x8b;
    file = dir.write(gz ? "in.nii.gz" : "in.nii", data, size);
  }
  int frame = 0;
  try {
    frame = imx::detail::read_nifti_header(file).frames - 1;
  } catch (const std::exception& e) {
    refused(e);
  }
  try {
    // The reader only: validate() and range() would double the time of large volumes.
    const imx::VolumeData v = imx::detail::read_nifti(file, frame);
    check_volume(v);
    accepted("volume");
  } catch (const std::exception& e) {
    refused(e);
  }
  fuzz_region(
      file, size > 0 ? data[size - 1] : 0,
      [](const auto& f) { return imx::detail::read_nifti_header(f); },
      [frame](const auto& f, const imx::VoxelBox& box) {
        return imx::detail::read_nifti_region(f, box, frame);
      });
  return 0;
}
