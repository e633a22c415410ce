// AFNI BRIK/HEAD reader: the input's first 2 bytes (little-endian) are the HEAD's length; the HEAD
// follows, then the BRIK (gzip data, a .BRIK.gz, is found by its magic), written as in+orig.HEAD
// and in+orig.BRIK. The last sub-brick is read, then the header and a region. Read through the
// format registry (imx::read_volume*), as a user's file is.
#include <algorithm>

#include "harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  if (size < 2) return 0;
  const ScratchDir& dir = scratch();
  dir.clear();
  const size_t head_size = std::min<size_t>(size - 2, data[0] | size_t{data[1]} << 8);
  const std::filesystem::path head = dir.write("in+orig.HEAD", data + 2, head_size);
  dir.write("in+orig.BRIK", data + 2 + head_size, size - 2 - head_size);
  fuzz_volume_file(head, size > 0 ? data[size - 1] : 0);
  return 0;
}
