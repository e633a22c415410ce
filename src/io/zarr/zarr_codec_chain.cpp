#include "io/zarr/zarr_codec_chain.hpp"

#include <cstring>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/zarr/crc32c.hpp"

namespace imx::detail {

namespace {

// Puts a chunk stored with its axes permuted by `order` back into C order of `shape`.
void untranspose(std::span<const uint8_t> stored, std::span<uint8_t> out,
                 std::span<const int64_t> shape, const std::vector<int>& order, size_t item) {
  const size_t n = shape.size();
  // Element stride in `out` of each encoded axis, walked in the encoded (stored) order.
  std::vector<size_t> out_stride(n, 1), encoded_stride(n), extent(n);
  for (size_t d = n - 1; d > 0; --d)
    out_stride[d - 1] = out_stride[d] * static_cast<size_t>(shape[d]);
  for (size_t a = 0; a < n; ++a) {
    extent[a] = static_cast<size_t>(shape[static_cast<size_t>(order[a])]);
    encoded_stride[a] = out_stride[static_cast<size_t>(order[a])];
  }
  std::vector<size_t> at(n, 0);
  size_t dst = 0;
  const size_t count = stored.size() / item;
  for (size_t src = 0; src < count; ++src) {
    std::memcpy(out.data() + dst * item, stored.data() + src * item, item);
    // Advance the encoded index, last axis fastest, keeping `dst` in step.
    for (size_t a = n; a-- > 0;) {
      if (++at[a] < extent[a]) {
        dst += encoded_stride[a];
        break;
      }
      dst -= (extent[a] - 1) * encoded_stride[a];
      at[a] = 0;
    }
  }
}

bool identity(const std::vector<int>& order) {
  for (size_t a = 0; a < order.size(); ++a)
    if (order[a] != static_cast<int>(a)) return false;
  return true;
}

}  // namespace

std::span<const uint8_t> strip_crc32c(std::span<const uint8_t> bytes, const std::string& what) {
  if (bytes.size() < 4)
    throw Error(
        fmt::format("{}: crc32c: {} bytes, too short to hold the checksum", what, bytes.size()));
  const std::span<const uint8_t> data = bytes.first(bytes.size() - 4);
  const uint8_t* c = bytes.data() + data.size();
  const uint32_t stored =
      uint32_t{c[0]} | uint32_t{c[1]} << 8 | uint32_t{c[2]} << 16 | uint32_t{c[3]} << 24;
  const uint32_t computed = crc32c(data);
  if (stored != computed)
    throw Error(fmt::format("{}: crc32c checksum mismatch (stored {:08x}, the data gives {:08x})",
                            what, stored, computed));
  return data;
}

void decode_zarr_chain(const ZarrCodecChain& chain, std::span<const uint8_t> stored,
                       std::span<uint8_t> out, std::span<const int64_t> shape, size_t item,
                       const std::string& what) {
  for (int k = 0; k < chain.checksums_outside; ++k) stored = strip_crc32c(stored, what);
  const bool permuted = !chain.order.empty() && !identity(chain.order);
  if (chain.checksums_inside == 0 && !permuted) {
    decode_zarr_chunk(chain.compressor, stored, out, what);
    return;
  }
  // Checksums inside the compressor, or a permutation: decoded into scratch first.
  std::vector<uint8_t> scratch(out.size() + 4 * static_cast<size_t>(chain.checksums_inside));
  decode_zarr_chunk(chain.compressor, stored, scratch, what);
  std::span<const uint8_t> data(scratch);
  for (int k = 0; k < chain.checksums_inside; ++k) data = strip_crc32c(data, what);
  if (permuted)
    untranspose(data, out, shape, chain.order, item);
  else
    std::memcpy(out.data(), data.data(), out.size());
}

}  // namespace imx::detail
