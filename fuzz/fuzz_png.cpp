// PNG reader (libspng), sRGB-decoded or linear by the last byte's low bit.
#include <exception>

#include "harness.hpp"
#include "intermix/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  std::filesystem::path file = dir.write("in.png", data, size);
  const bool linear = size > 0 && (data[size - 1] & 1) != 0;
  try {
    imx::Image image = imx::read_png(file, linear);
    accepted("image");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
