// MRtrix track reader (io/streamlines/tck.hpp): the input is a .tck file, optionally followed by
// kDataMarker and a .tsf file of scalars for it. The tracks go through the text header, the walk
// over NaN-delimited records and the conversion to LPS; the scalars through the same layout and
// their pairing with the tracks' streamlines.
#include <exception>

#include "harness.hpp"
#include "io/streamlines/tck.hpp"
#include "streamlines_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const Split parts = split_at(as_view(data, size), kDataMarker);
  const std::filesystem::path tck = dir.write("in.tck", parts.head.data(), parts.head.size());
  try {
    std::vector<std::string> notes;
    imx::Streamlines s = imx::detail::read_tck(tck, notes);
    check_streamlines(s);
    accepted("tck");
    if (parts.found) {
      const std::filesystem::path tsf = dir.write("in.tsf", parts.tail.data(), parts.tail.size());
      imx::detail::read_tsf(tsf, s, notes, tck);
      check_streamlines(s);
      accepted("tsf");
    }
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
