#include "io/zarr/zarr_codecs.hpp"

#include <cstring>

#include <blosc.h>
#include <fmt/format.h>
#include <zstd.h>
#include <zstd_errors.h>

#include "intermix/error.hpp"
#include "io/streams/bounded_inflate.hpp"

namespace imx::detail {

namespace {

Error wrong_size(const std::string& what, const char* codec, size_t got, size_t want) {
  return Error(
      fmt::format("{}: {} chunk decompresses to {} bytes, expected {} (the chunk's size "
                  "from its metadata)",
                  what, codec, got, want));
}

// A chunk bomb: the data holds more than the chunk's size, which is all that was made room for.
Error too_large(const std::string& what, const char* codec, size_t want) {
  return Error(
      fmt::format("{}: {} chunk decompresses to more than {} bytes (the chunk's size "
                  "from its metadata)",
                  what, codec, want));
}

void zstd_chunk(std::span<const uint8_t> stored, std::span<uint8_t> out, const std::string& what) {
  const unsigned long long declared = ZSTD_getFrameContentSize(stored.data(), stored.size());
  if (declared == ZSTD_CONTENTSIZE_ERROR)
    throw Error(fmt::format("{}: corrupt zstd chunk (not a zstd frame)", what));
  if (declared != ZSTD_CONTENTSIZE_UNKNOWN && declared != out.size())
    throw wrong_size(what, "zstd", static_cast<size_t>(declared), out.size());
  // A destination of exactly the chunk's size: more data fails as "destination too small".
  const size_t got = ZSTD_decompress(out.data(), out.size(), stored.data(), stored.size());
  if (ZSTD_isError(got)) {
    if (ZSTD_getErrorCode(got) == ZSTD_error_dstSize_tooSmall)
      throw too_large(what, "zstd", out.size());
    throw Error(fmt::format("{}: corrupt zstd chunk ({})", what, ZSTD_getErrorName(got)));
  }
  if (got != out.size()) throw wrong_size(what, "zstd", got, out.size());
}

void blosc_chunk(std::span<const uint8_t> stored, std::span<uint8_t> out, const std::string& what) {
  if (stored.size() < BLOSC_MIN_HEADER_LENGTH)
    throw Error(fmt::format("{}: truncated blosc chunk ({} bytes, shorter than its {}-byte header)",
                            what, stored.size(), BLOSC_MIN_HEADER_LENGTH));
  size_t nbytes = 0, cbytes = 0, blocksize = 0;
  blosc_cbuffer_sizes(stored.data(), &nbytes, &cbytes, &blocksize);
  if (cbytes > stored.size())
    throw Error(fmt::format("{}: truncated blosc chunk: its header says {} bytes, the file has {}",
                            what, cbytes, stored.size()));
  if (nbytes != out.size()) throw wrong_size(what, "blosc", nbytes, out.size());
  size_t valid = 0;
  if (blosc_cbuffer_validate(stored.data(), stored.size(), &valid) != 0 || valid != out.size())
    throw Error(fmt::format("{}: corrupt blosc chunk header", what));
  if (out.empty()) return;
  const int got = blosc_decompress_ctx(stored.data(), out.data(), out.size(), 1);
  if (got < 0 || static_cast<size_t>(got) != out.size())
    throw Error(fmt::format("{}: corrupt blosc chunk (blosc error {})", what, got));
}

}  // namespace

const char* zarr_compressor_name(ZarrCompressor compressor) {
  switch (compressor) {
    case ZarrCompressor::none:
      return "null";
    case ZarrCompressor::zlib:
      return "zlib";
    case ZarrCompressor::gzip:
      return "gzip";
    case ZarrCompressor::blosc:
      return "blosc";
    case ZarrCompressor::zstd:
      return "zstd";
  }
  return "?";
}

void decode_zarr_chunk(ZarrCompressor compressor, std::span<const uint8_t> stored,
                       std::span<uint8_t> out, const std::string& what) {
  switch (compressor) {
    case ZarrCompressor::none:
      if (stored.size() != out.size())
        throw Error(
            fmt::format("{}: uncompressed chunk holds {} bytes, expected {} (the chunk's "
                        "size from its metadata)",
                        what, stored.size(), out.size()));
      if (!out.empty()) std::memcpy(out.data(), stored.data(), out.size());
      return;
    case ZarrCompressor::zlib:
      return inflate_exactly(stored, out, "zlib chunk", what);
    case ZarrCompressor::gzip:
      return inflate_exactly(stored, out, "gzip chunk", what);
    case ZarrCompressor::zstd:
      return zstd_chunk(stored, out, what);
    case ZarrCompressor::blosc:
      return blosc_chunk(stored, out, what);
  }
}

}  // namespace imx::detail
