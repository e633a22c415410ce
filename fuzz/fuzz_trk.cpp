// TrackVis reader (io/streamlines/trk.hpp): the input is a .trk file. It goes through the header
// (byte order from hdr_size, version, voxel order, vox_to_ras, scalar and property names), the
// walk that checks every point count against the file, and the conversion to LPS.
#include <exception>

#include "harness.hpp"
#include "io/streamlines/trk.hpp"
#include "streamlines_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const std::filesystem::path file = dir.write("in.trk", data, size);
  try {
    std::vector<std::string> notes;
    check_streamlines(imx::detail::read_trk(file, notes));
    accepted("trk");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
