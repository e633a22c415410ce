// NRRD reader: an attached .nrrd, or (input holding the data marker) a detached .nhdr header
// with its data file "data.raw" beside it.
#include <exception>

#include "harness.hpp"
#include "intermix/io.hpp"
#include "io/nrrd.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  Split parts = split_at(as_view(data, size), kDataMarker);
  std::filesystem::path file;
  if (parts.found) {
    file = dir.write("in.nhdr", std::string(parts.head) + "\n");
    dir.write("data.raw", parts.tail);
  } else {
    file = dir.write("in.nrrd", parts.head);
  }
  try {
    // The reader only: validate() and range() would double the time of large volumes.
    const imx::VolumeData v = imx::detail::read_nrrd(file);
    check_volume(v);
    accepted("volume");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
