// The codecs one Zarr chunk passes through, in the order they decode: checksums (Zarr v3's
// crc32c), at most one compressor, and a transposition of the chunk's axes. A Zarr v2 array's
// chain is its compressor alone.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/zarr/zarr_codecs.hpp"

namespace imx::detail {

struct ZarrCodecChain {
  ZarrCompressor compressor = ZarrCompressor::none;
  int checksums_outside = 0;  // crc32c codecs after the compressor (encoding order)
  int checksums_inside = 0;   // crc32c codecs before it: checked after decompression
  // v3 "transpose": encoded axis a is decoded axis order[a]; empty: C order as stored.
  std::vector<int> order;
};

// Decodes one chunk's stored bytes into `out` (the chunk of `shape`, elements of `item` bytes,
// C order): each checksum verified (a mismatch throws imx::Error naming `what` and "crc32c"),
// decompressed to exactly the size `out` needs, then put back into C order.
void decode_zarr_chain(const ZarrCodecChain& chain, std::span<const uint8_t> stored,
                       std::span<uint8_t> out, std::span<const int64_t> shape, size_t item,
                       const std::string& what);

// Verifies and drops the 4-byte little-endian CRC-32C that ends `bytes`; throws naming `what`.
std::span<const uint8_t> strip_crc32c(std::span<const uint8_t> bytes, const std::string& what);

}  // namespace imx::detail
