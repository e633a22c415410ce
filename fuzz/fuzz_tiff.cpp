// TIFF, BigTIFF, ImageJ and OME-TIFF volumes through libtiff: the input is one TIFF file, read
// through the format registry as a user's file is (its header, last frame, then a region); or,
// when it holds kDataMarker, two TIFF files "z1.tif" and "z2.tif" in a folder, read as a stack.
#include <filesystem>

#include "harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const Split parts = split_at(as_view(data, size), kDataMarker);
  std::filesystem::path input;
  if (parts.found) {
    std::filesystem::create_directories(dir.path() / "stack");
    dir.write("stack/z1.tif", parts.head);
    dir.write("stack/z2.tif", parts.tail);
    input = dir.path() / "stack";
  } else {
    // An OME-TIFF's TiffData may name its own file: this one's name.
    input = dir.write("in.ome.tif", parts.head);
  }
  fuzz_volume_file(input, size > 0 ? data[size - 1] : 0);
  return 0;
}
