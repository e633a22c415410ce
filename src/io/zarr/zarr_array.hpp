// One Zarr array, v2 (.zarray) or v3 (zarr.json): its shape, chunk grid, element type, fill value
// and codecs, and its chunks: one file each, named by their indices (v2's "0.1.2" or "0/1/2",
// v3's "c/0/1/2"), or inner chunks of such files (v3 shards).
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "io/voxels/raw_voxels.hpp"
#include "io/zarr/zarr_codec_chain.hpp"

namespace imx::detail {

// Zarr v3's sharding_indexed codec: each chunk file (a shard) holds a grid of inner chunks and an
// index of where each lies (a uint64 offset and size, both 2^64-1 for an inner chunk not written).
struct ZarrShard {
  std::vector<int64_t> shape;      // the shard's (the chunk grid's chunk) shape
  std::vector<int64_t> per_shard;  // inner chunks per shard, per dimension
  uint64_t inner_chunks = 0;       // their product: the index's entries
  bool index_at_start = false;     // index_location "start" (default "end")
  bool index_big_endian = false;
  int index_checksums = 0;  // crc32c codecs after the index's "bytes"

  uint64_t index_bytes() const { return inner_chunks * 16 + 4 * uint64_t(index_checksums); }
};

struct ZarrArray {
  std::filesystem::path dir;  // the array's folder (holds .zarray or zarr.json)
  std::string what;           // the metadata file, for messages
  int zarr_format = 2;
  std::vector<int64_t> shape;
  std::vector<int64_t> chunks;  // what one decode gives: an inner chunk when sharded
  RawType type = RawType::u8;
  bool big_endian = false;
  std::vector<uint8_t> fill;  // one element in file byte order: what a missing chunk holds
  ZarrCodecChain codecs;      // of one chunk (one inner chunk when sharded)
  std::string key_prefix;     // v3 "default" key encoding: "c"; v2 and v3 "v2": none
  char separator = '.';
  std::optional<ZarrShard> shard;
  std::vector<std::string> dimension_names;  // v3's, when given
  size_t chunk_bytes = 0;  // one chunk's decoded size: edge chunks are stored full-size

  // The file of the chunk (or, sharded, the shard) at `index` of the file grid.
  std::filesystem::path chunk_file(std::span<const int64_t> index) const;
  // The shape one file holds: the shard's when sharded, else the chunk's.
  const std::vector<int64_t>& file_chunks() const { return shard ? shard->shape : chunks; }
};

// Parses .zarray text (of `dir`, named `what` in messages). Throws imx::Error naming `what` and
// the field for anything not read: order "F", filters, other compressors, other dtypes, shapes
// whose chunks would exceed the memory budget.
ZarrArray parse_zarray(std::string_view text, const std::filesystem::path& dir,
                       const std::string& what);
// Parses a Zarr v3 array's zarr.json text: refuses by name other data types, chunk grids and key
// encodings, storage transformers, unknown codecs and extensions that must be understood.
ZarrArray parse_zarr_json_array(std::string_view text, const std::filesystem::path& dir,
                                const std::string& what);

// parse_zarray on `dir`/.zarray.
ZarrArray read_zarray(const std::filesystem::path& dir);
// The array in `dir`: zarr.json (v3) when present, else .zarray (v2).
ZarrArray read_zarr_array(const std::filesystem::path& dir);
// A Zarr metadata file's whole text, refused (naming it) past `max_bytes` or when unreadable.
std::string read_zarr_metadata(const std::filesystem::path& file, uintmax_t max_bytes);

// The bytes of one chunk (array.chunk_bytes) decoded from `stored` (the chunk file's content, or
// an inner chunk's bytes in its shard).
void decode_zarr_chunk(const ZarrArray& array, std::span<const uint8_t> stored,
                       std::span<uint8_t> out, const std::string& what);

// Decodes the chunks one stored file holds, from memory (`file`: a chunk file, or a whole shard
// with its index), at most `max_chunks` of them, each into a buffer of array.chunk_bytes: the
// path from bytes to voxels without the folder, for fuzzing and seed checks. The chunks decoded.
size_t decode_zarr_file(const ZarrArray& array, std::span<const uint8_t> file, size_t max_chunks,
                        const std::string& what);

// Copies the box `box` (x, y, z: the last three dimensions, inside them) of `array` at `lead`
// (the indices of the dimensions before them: time, channel) into `out` (x fastest, file byte
// order), reading each chunk the box touches once, and no other.
void read_zarr_block(const ZarrArray& array, std::span<const int64_t> lead, const VoxelBox& box,
                     std::span<uint8_t> out);

}  // namespace imx::detail
