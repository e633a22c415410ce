// TRX reader (io/streamlines/trx.hpp): the input is a .trx zip archive (stored or deflated
// members). Every array must be checked against header.json's counts before anything is
// allocated or inflated; what it returns must be whole: offsets from 0 to the point count, every
// streamline of 2 points or more, every point finite, one value per point or streamline in every
// array, group members ascending and naming streamlines that exist.
#include "io/streamlines/trx.hpp"
#include "streamlines_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return imx::fuzz::fuzz_streamline_reader(data, size, "in.trx", imx::detail::read_trx);
}
