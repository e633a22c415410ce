// MRtrix reader: the input is a .mif (gzip data, a .mif.gz, is found by its magic); when it holds
// kDataMarker, the part before it is a .mih header and the part after it its data file, in.dat.
// The last volume is read, then the header and a region. Read through the format registry
// (imx::read_volume*), as a user's file is.

#include "harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const Split parts = split_at(as_view(data, size), kDataMarker);
  const std::filesystem::path file = dir.write(parts.found ? "in.mih" : "in.mif", parts.head);
  if (parts.found) dir.write("in.dat", parts.tail);
  fuzz_volume_file(file, size > 0 ? data[size - 1] : 0);
  return 0;
}
