#include "io/zarr/zarr_shard.hpp"

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx::detail {

std::vector<ZarrShardEntry> parse_zarr_shard_index(const ZarrShard& shard,
                                                   std::span<const uint8_t> index,
                                                   uint64_t file_bytes, uint64_t most_bytes,
                                                   const std::string& what) {
  if (index.size() != shard.index_bytes())
    throw Error(fmt::format("{}: shard index of {} bytes, expected {}", what, index.size(),
                            shard.index_bytes()));
  if (file_bytes < shard.index_bytes())
    throw Error(fmt::format("{}: shard file of {} bytes, shorter than its {}-byte index", what,
                            file_bytes, shard.index_bytes()));
  std::span<const uint8_t> data = index;
  for (int k = 0; k < shard.index_checksums; ++k) data = strip_crc32c(data, what + " (index)");
  // Outside the index: the bytes inner chunks may lie in.
  const uint64_t lo = shard.index_at_start ? shard.index_bytes() : 0;
  const uint64_t hi = shard.index_at_start ? file_bytes : file_bytes - shard.index_bytes();
  const auto word = [&](size_t at) {
    uint64_t v = 0;
    for (int b = 0; b < 8; ++b) {
      const uint64_t byte = data[at + (shard.index_big_endian ? b : 7 - b)];
      v = v << 8 | byte;
    }
    return v;
  };
  std::vector<ZarrShardEntry> entries(static_cast<size_t>(shard.inner_chunks));
  for (size_t n = 0; n < entries.size(); ++n) {
    ZarrShardEntry& e = entries[n];
    e.offset = word(16 * n);
    e.nbytes = word(16 * n + 8);
    constexpr uint64_t kNone = ~uint64_t{0};
    if (e.offset == kNone && e.nbytes == kNone) {
      e.missing = true;
      continue;
    }
    if (e.nbytes > most_bytes)
      throw Error(fmt::format(
          "{}: shard index entry {} says {} bytes, more than any encoding of an inner chunk "
          "({} bytes)",
          what, n, e.nbytes, most_bytes));
    if (e.offset < lo || e.offset > hi || e.nbytes > hi - e.offset)
      throw Error(fmt::format(
          "{}: shard index entry {} says bytes {} to {}, outside the shard's data ({} to {})", what,
          n, e.offset, e.offset + e.nbytes, lo, hi));
  }
  return entries;
}

}  // namespace imx::detail
