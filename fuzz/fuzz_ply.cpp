// The hand-written PLY reader (ascii, binary little- and big-endian), through read_mesh.
#include <exception>

#include "harness.hpp"
#include "intermix/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  std::filesystem::path file = dir.write("in.ply", data, size);
  try {
    check_mesh(imx::read_mesh(file));
    accepted("mesh");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
