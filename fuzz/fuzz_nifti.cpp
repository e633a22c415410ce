// NIfTI-1 reader (nifticlib): gzip data (magic 1f 8b) is read as .nii.gz, anything else as .nii.
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
  return 0;
}
