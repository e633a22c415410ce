// One Zarr v2 array: its .zarray metadata (shape, chunks, dtype, fill value, compressor) and its
// chunks, each one file named by its chunk indices (zarr's "0.1.2" or "0/1/2").
#pragma once
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "io/voxels/raw_voxels.hpp"
#include "io/zarr/zarr_codecs.hpp"

namespace imx::detail {

struct ZarrArray {
  std::filesystem::path dir;  // the array's folder (holds .zarray)
  std::string what;           // the .zarray file, for messages
  std::vector<int64_t> shape, chunks;
  RawType type = RawType::u8;
  bool big_endian = false;
  std::vector<uint8_t> fill;  // one element in file byte order: what a missing chunk holds
  ZarrCompressor compressor = ZarrCompressor::none;
  char separator = '.';
  size_t chunk_bytes = 0;  // one chunk's decoded size: edge chunks are stored full-size

  // The file of the chunk at `index` (one per dimension).
  std::filesystem::path chunk_file(std::span<const int64_t> index) const;
};

// Parses .zarray text (of `dir`, named `what` in messages). Throws imx::Error naming `what` and
// the field for anything not read: order "F", filters, other compressors, other dtypes, shapes
// whose chunks would exceed the memory budget.
ZarrArray parse_zarray(std::string_view text, const std::filesystem::path& dir,
                       const std::string& what);

// parse_zarray on `dir`/.zarray.
ZarrArray read_zarray(const std::filesystem::path& dir);
// A Zarr metadata file's whole text, refused (naming it) past `max_bytes` or when unreadable.
std::string read_zarr_metadata(const std::filesystem::path& file, uintmax_t max_bytes);

// One chunk's decoded bytes (array.chunk_bytes, file byte order, C order): its file decoded, or
// the fill value when the file is missing (as zarr reads it).
void read_zarr_chunk(const ZarrArray& array, std::span<const int64_t> index,
                     std::span<uint8_t> out);

// The bytes of one chunk (array.chunk_bytes) decoded from `stored` (the chunk file's content).
void decode_zarr_chunk(const ZarrArray& array, std::span<const uint8_t> stored,
                       std::span<uint8_t> out, const std::string& what);

// Copies the whole grid of the last three dimensions of `array` at `lead` (the indices of the
// dimensions before them: time, channel) into `out` (x fastest, file byte order), reading each
// chunk that grid touches once.
void read_zarr_block(const ZarrArray& array, std::span<const int64_t> lead, std::span<uint8_t> out);

}  // namespace imx::detail
