// The zlib inflate loop behind gzip-encoded NRRD / MetaImage voxels (imx::detail::gunzip).
// Byte 0: low 4 bits choose how many inflated bytes to skip (n * 1000), high 4 bits the output
// size (16 << n bytes, at most 512 KiB); the rest is the gzip or zlib stream.
#include <exception>
#include <sstream>
#include <vector>

#include "harness.hpp"
#include "io/streams/gzip.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  if (size < 1) return 0;
  const size_t skip = static_cast<size_t>(data[0] & 0x0f) * 1000;
  const size_t out_size = size_t{16} << (data[0] >> 4);
  std::istringstream in(std::string(reinterpret_cast<const char*>(data + 1), size - 1));
  std::vector<uint8_t> out(out_size);
  try {
    size_t n = imx::detail::gunzip(in, skip, out, "fuzz");
    if (n > out.size()) __builtin_trap();
    accepted("stream");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
