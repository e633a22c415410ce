// zlib or gzip data inflated into a buffer of exactly the size its container claims: the
// inflating half of the one bounded-inflate layer (inflate_charge.hpp charges the claim first).
// Zarr chunks and VTK XML's compressed blocks inflate through here.
#pragma once
#include <cstdint>
#include <span>
#include <string>

namespace imx::detail {

// Inflates `stored` (zlib or gzip, detected from its header) into `out`, which it must fill
// exactly. Never writes past `out` and allocates only zlib's window: data that would inflate
// past the claim is refused at its first surplus byte. Throws imx::Error naming `what` and
// `kind` ("zlib chunk", "compressed block 3") for data that holds more or fewer bytes than `out`
// or is corrupt.
void inflate_exactly(std::span<const uint8_t> stored, std::span<uint8_t> out, const char* kind,
                     const std::string& what);

}  // namespace imx::detail
