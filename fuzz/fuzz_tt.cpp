// DSI Studio TinyTrack reader (io/streamlines/tt.hpp): the input is a .tt.gz file (gzip or raw
// MATLAB v4, found by its magic). Its matrix headers and streamline records must be checked
// against the bytes left; what it returns must be whole: offsets from 0 to the point count,
// rising, every streamline of 2 points or more, every point finite.
#include "io/streamlines/tt.hpp"
#include "streamlines_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return imx::fuzz::fuzz_streamline_reader(data, size, "in.tt.gz", imx::detail::read_tt);
}
