// The index of a Zarr v3 shard (sharding_indexed): where each inner chunk's bytes lie in the
// shard file, checked against the file before any of them is read.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/zarr/zarr_array.hpp"

namespace imx::detail {

struct ZarrShardEntry {
  uint64_t offset = 0, nbytes = 0;  // from the shard file's start
  bool missing = false;             // both 2^64-1: the inner chunk holds the fill value
};

// Decodes a shard's index (exactly shard.index_bytes() bytes, its checksums verified) of a shard
// file of `file_bytes`. Each entry present must lie in the file outside the index and hold at most
// `most_bytes` (what any encoding of one inner chunk takes); else imx::Error naming `what`.
std::vector<ZarrShardEntry> parse_zarr_shard_index(const ZarrShard& shard,
                                                   std::span<const uint8_t> index,
                                                   uint64_t file_bytes, uint64_t most_bytes,
                                                   const std::string& what);

}  // namespace imx::detail
