// The compressors of Zarr chunks (numcodecs' zlib, gzip, blosc, zstd; v3's gzip, zstd, blosc): one
// chunk's stored bytes decoded into a buffer of exactly the size the array's metadata gives it.
#pragma once
#include <cstdint>
#include <span>
#include <string>

namespace imx::detail {

enum class ZarrCompressor : uint8_t { none, zlib, gzip, blosc, zstd };

// "null", "zlib", "gzip", "blosc", "zstd": numcodecs' ids.
const char* zarr_compressor_name(ZarrCompressor compressor);

// Decodes `stored` into `out`, which it must fill exactly: data that decodes to fewer or more
// bytes (a truncated chunk, a chunk bomb) or is corrupt throws imx::Error naming `what` (the
// chunk file). Never writes past `out` nor allocates more than a fixed scratch.
void decode_zarr_chunk(ZarrCompressor compressor, std::span<const uint8_t> stored,
                       std::span<uint8_t> out, const std::string& what);

}  // namespace imx::detail
