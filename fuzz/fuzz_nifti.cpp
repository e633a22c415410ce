// NIfTI-1 reader (nifticlib): gzip data (magic 1f 8b) is read as .nii.gz, anything else as .nii;
// then its header and a region of it (fuzz_region).
#include <exception>

#include "harness.hpp"
#include "intermix/io.hpp"
#include "io/nifti.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const bool gz = size >= 2 && data[0] == 0x1f && data[1] == 0x8b;
  std::filesystem::path file = dir.write(gz ? "in.nii.gz" : "in.nii", data, size);
  try {
    // The reader only: validate() and range() would double the time of large volumes.
    const imx::VolumeData v = imx::detail::read_nifti(file);
    check_volume(v);
    accepted("volume");
  } catch (const std::exception& e) {
    refused(e);
  }
  fuzz_region(
      file, size > 0 ? data[size - 1] : 0,
      [](const auto& f) { return imx::detail::read_nifti_header(f); },
      [](const auto& f, const imx::VoxelBox& box) {
        return imx::detail::read_nifti_region(f, box);
      });
  return 0;
}
