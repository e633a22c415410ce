// MINC reader: the input is a .mnc file, MINC-2 (HDF5, parsed by libhdf5: this target is what
// exercises libhdf5 on hostile input) or MINC-1 (refused). The last frame is read, then the header
// and a region of that frame (fuzz_region). Seeds: small MINC-2 files (nibabel's test data, or
// tests/io/minc_test.cpp's), so that mutations reach the attributes and the scaling. Read through
// the format registry (imx::read_volume*), as a user's file is.

#include "harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const std::filesystem::path file = dir.write("in.mnc", data, size);
  fuzz_volume_file(file, size > 0 ? data[size - 1] : 0);
  return 0;
}
