// Philips PAR/REC reader: the input is a PAR header text, then kDataMarker, then the REC bytes
// (written as in.PAR and in.REC); without the marker the whole input is the PAR and the REC is
// empty. The last frame is read, so that the slice sorting of every volume is reached; then the
// header and a region of that frame (fuzz_region). Read through the format registry
// (imx::read_volume*), as a user's file is.

#include "harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const Split parts = split_at(as_view(data, size), kDataMarker);
  const std::filesystem::path par = dir.write("in.PAR", parts.head);
  dir.write("in.REC", parts.tail);
  fuzz_volume_file(par, size > 0 ? data[size - 1] : 0);
  return 0;
}
