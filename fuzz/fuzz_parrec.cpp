// Philips PAR/REC reader: the input is a PAR header text, then kDataMarker, then the REC bytes
// (written as in.PAR and in.REC); without the marker the whole input is the PAR and the REC is
// empty. The last frame is read, so that the slice sorting of every volume is reached; then the
// header and a region of that frame (fuzz_region). Read through the format registry
// (imx::read_volume*), as a user's file is.
#include <exception>

#include "harness.hpp"
#include "intermix/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const Split parts = split_at(as_view(data, size), kDataMarker);
  const std::filesystem::path par = dir.write("in.PAR", parts.head);
  dir.write("in.REC", parts.tail);
  int frame = 0;
  try {
    frame = imx::read_volume_header(par).frames - 1;
  } catch (const std::exception& e) {
    refused(e);
  }
  try {
    check_volume(imx::read_volume(par, frame));
    accepted("volume");
  } catch (const std::exception& e) {
    refused(e);
  }
  fuzz_region(
      par, size > 0 ? data[size - 1] : 0, [](const auto& f) { return imx::read_volume_header(f); },
      [frame](const auto& f, const imx::VoxelBox& box) {
        return imx::read_volume_region(f, box, frame);
      });
  return 0;
}
