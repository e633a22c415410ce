#include "io/zarr/zarr_array.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <exception>
#include <fstream>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/input_file.hpp"
#include "io/zarr/zarr_metadata_fields.hpp"
#include "io/zarr/zarr_shard.hpp"

namespace imx::detail {

namespace {

// Chunk reads one volume may take: each is a file to open (or an inner chunk to seek to), so tiny
// chunks of a large grid would take hours (a 2048^3 grid in 64^3 chunks has 32768).
constexpr uint64_t kMaxChunksPerGrid = uint64_t{1} << 20;

void fill_chunk(const ZarrArray& array, std::span<uint8_t> out) {
  const size_t n = array.fill.size();
  for (size_t i = 0; i + n <= out.size(); i += n) std::memcpy(out.data() + i, array.fill.data(), n);
}

// The most bytes any encoding here makes of `bytes`: no codec expands data by more than a few
// percent and a block header (and a checksum or two).
uint64_t most_stored(size_t bytes) {
  return uint64_t{bytes} + bytes / 8 + 65536;
}

std::vector<uint8_t> read_range(std::ifstream& in, uint64_t offset, uint64_t size,
                                const std::string& what) {
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  in.clear();
  in.seekg(static_cast<std::streamoff>(offset));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
  if (!in || static_cast<uint64_t>(in.gcount()) != size)
    throw Error(fmt::format("{}: could not read {} bytes at {}", what, size, offset));
  return bytes;
}

// Reads the chunks of one array, one open shard at a time (its index read once).
class ChunkReader {
 public:
  explicit ChunkReader(const ZarrArray& array) : array_(array) {}

  // The chunk at `index` (of the grid of array.chunks) into `out` (array.chunk_bytes).
  void read(std::span<const int64_t> index, std::span<uint8_t> out) {
    if (!array_.shard) return read_file(index, out);
    const ZarrShard& shard = *array_.shard;
    std::vector<int64_t> outer(index.size());
    uint64_t slot = 0;  // the inner chunk's entry: C order in the shard's grid
    for (size_t d = 0; d < index.size(); ++d) {
      outer[d] = index[d] / shard.per_shard[d];
      slot = slot * static_cast<uint64_t>(shard.per_shard[d]) +
             static_cast<uint64_t>(index[d] % shard.per_shard[d]);
    }
    open_shard(array_.chunk_file(outer));
    if (shard_missing_ || entries_[slot].missing) return fill_chunk(array_, out);
    const ZarrShardEntry& e = entries_[slot];
    const std::vector<uint8_t> stored = read_range(in_, e.offset, e.nbytes, shard_what_);
    decode_zarr_chunk(array_, stored, out, fmt::format("{} (inner chunk {})", shard_what_, slot));
  }

 private:
  void read_file(std::span<const int64_t> index, std::span<uint8_t> out) {
    const std::filesystem::path file = array_.chunk_file(index);
    const std::string what = file.string();
    std::ifstream in;
    // A chunk zarr never wrote holds the fill value everywhere.
    const std::optional<uint64_t> size = open(file, in);
    if (!size) return fill_chunk(array_, out);
    if (*size > most_stored(array_.chunk_bytes))
      throw Error(
          fmt::format("{}: chunk file of {} bytes, more than any {} encoding of its {} bytes", what,
                      *size, zarr_compressor_name(array_.codecs.compressor), array_.chunk_bytes));
    decode_zarr_chunk(array_, read_range(in, 0, *size, what), out, what);
  }

  // Opens `file` into `in`: its size, or nullopt when there is no such file.
  static std::optional<uint64_t> open(const std::filesystem::path& file, std::ifstream& in) {
    const std::string what = file.string();
    InputFd fd;
    try {
      fd = open_input(file, fmt::format("{} (chunk file)", what));
    } catch (const FileError& e) {
      if (e.code() == ENOENT) return std::nullopt;  // a chunk zarr never wrote
      throw;
    }
    in.open(path_of_open(fd, file), std::ios::binary);
    if (!in) throw FileError(fmt::format("{}: cannot open chunk file", what), errno);
    return fd.size();
  }

  void open_shard(const std::filesystem::path& file) {
    if (file == shard_file_ && !shard_what_.empty()) return;
    shard_file_ = file;
    shard_what_ = file.string();
    in_ = std::ifstream();
    entries_.clear();
    const std::optional<uint64_t> size = open(file, in_);
    shard_missing_ = !size;
    if (shard_missing_) return;
    const ZarrShard& shard = *array_.shard;
    // The index's size comes from the metadata: a file shorter than it is refused before the
    // index (or anything it claims) is allocated.
    const uint64_t index_bytes = shard.index_bytes();
    if (*size < index_bytes)
      throw Error(fmt::format("{}: shard file of {} bytes, shorter than its {}-byte index",
                              shard_what_, *size, index_bytes));
    const std::vector<uint8_t> index =
        read_range(in_, shard.index_at_start ? 0 : *size - index_bytes, index_bytes, shard_what_);
    entries_ =
        parse_zarr_shard_index(shard, index, *size, most_stored(array_.chunk_bytes), shard_what_);
  }

  const ZarrArray& array_;
  std::filesystem::path shard_file_;
  std::string shard_what_;
  std::ifstream in_;
  bool shard_missing_ = false;
  std::vector<ZarrShardEntry> entries_;
};

}  // namespace

std::filesystem::path ZarrArray::chunk_file(std::span<const int64_t> index) const {
  std::string key = key_prefix;
  for (size_t d = 0; d < index.size(); ++d) {
    if (d || !key.empty()) key += separator;
    key += std::to_string(index[d]);
  }
  return dir / key;
}

std::string read_zarr_metadata(const std::filesystem::path& file, uintmax_t max_bytes) {
  const std::string what = file.string();
  const InputFd fd = open_input(file, what);
  const uint64_t size = fd.size();
  if (size > max_bytes)
    throw Error(
        fmt::format("{}: {} bytes, more than {} (not Zarr metadata)", what, size, max_bytes));
  std::ifstream in(path_of_open(fd, file), std::ios::binary);
  if (!in) throw FileError(fmt::format("{}: cannot open file", what), errno);
  std::string text(static_cast<size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (static_cast<uintmax_t>(in.gcount()) != size)
    throw Error(fmt::format("{}: could not read the whole file", what));
  return text;
}

ZarrArray read_zarr_array(const std::filesystem::path& dir) {
  const std::filesystem::path v3 = dir / "zarr.json";
  std::error_code ec;
  if (!std::filesystem::exists(v3, ec)) return read_zarray(dir);
  return parse_zarr_json_array(read_zarr_metadata(v3, kMaxZarrMetadataBytes), dir, v3.string());
}

void decode_zarr_chunk(const ZarrArray& array, std::span<const uint8_t> stored,
                       std::span<uint8_t> out, const std::string& what) {
  if (out.size() != array.chunk_bytes)
    throw Error(fmt::format("{}: internal: chunk buffer of {} bytes, expected {}", what, out.size(),
                            array.chunk_bytes));
  decode_zarr_chain(array.codecs, stored, out, array.chunks, raw_type_size(array.type), what);
}

size_t decode_zarr_file(const ZarrArray& array, std::span<const uint8_t> file, size_t max_chunks,
                        const std::string& what) {
  std::vector<uint8_t> chunk(array.chunk_bytes);
  if (!array.shard) {
    if (max_chunks == 0) return 0;
    decode_zarr_chunk(array, file, chunk, what);
    return 1;
  }
  const ZarrShard& shard = *array.shard;
  if (file.size() < shard.index_bytes())
    throw Error(fmt::format("{}: shard file of {} bytes, shorter than its {}-byte index", what,
                            file.size(), shard.index_bytes()));
  const size_t index_bytes = static_cast<size_t>(shard.index_bytes());
  const auto index = shard.index_at_start ? file.first(index_bytes) : file.last(index_bytes);
  const std::vector<ZarrShardEntry> entries =
      parse_zarr_shard_index(shard, index, file.size(), most_stored(array.chunk_bytes), what);
  size_t decoded = 0;
  for (const ZarrShardEntry& e : entries) {
    if (e.missing) continue;
    if (decoded == max_chunks) break;
    decode_zarr_chunk(array, file.subspan(e.offset, e.nbytes), chunk, what);
    ++decoded;
  }
  return decoded;
}

void read_zarr_block(const ZarrArray& array, std::span<const int64_t> lead, const VoxelBox& box,
                     std::span<uint8_t> out) {
  const size_t n = array.shape.size();
  if (n < 3 || lead.size() != n - 3)
    throw Error(fmt::format("{}: internal: {} leading indices for {} dimensions", array.what,
                            lead.size(), n));
  const size_t item = raw_type_size(array.type);
  const int64_t X = box.hi.x - box.lo.x, Y = box.hi.y - box.lo.y, Z = box.hi.z - box.lo.z;
  if (out.size() != box.count() * item)
    throw Error(fmt::format("{}: internal: block buffer of {} bytes", array.what, out.size()));
  // Element strides of one chunk, C order.
  std::vector<size_t> stride(n, 1);
  for (size_t d = n - 1; d > 0; --d)
    stride[d - 1] = stride[d] * static_cast<size_t>(array.chunks[d]);
  std::vector<int64_t> index(n);
  size_t lead_offset = 0;
  for (size_t d = 0; d + 3 < n; ++d) {
    index[d] = lead[d] / array.chunks[d];
    lead_offset += static_cast<size_t>(lead[d] % array.chunks[d]) * stride[d];
  }
  const int64_t cx = array.chunks[n - 1], cy = array.chunks[n - 2], cz = array.chunks[n - 3];
  // The chunks the box touches: [first, last] per axis.
  const glm::i64vec3 first(box.lo.x / cx, box.lo.y / cy, box.lo.z / cz);
  const glm::i64vec3 last((box.hi.x - 1) / cx, (box.hi.y - 1) / cy, (box.hi.z - 1) / cz);
  const uint64_t grid_chunks = static_cast<uint64_t>(last.x - first.x + 1) *
                               static_cast<uint64_t>(last.y - first.y + 1) *
                               static_cast<uint64_t>(last.z - first.z + 1);
  if (grid_chunks > kMaxChunksPerGrid)
    throw Error(
        fmt::format("{}: field 'chunks': a {}x{}x{} grid in chunks of {}x{}x{} is {} chunk "
                    "reads, more than {}",
                    array.what, X, Y, Z, cx, cy, cz, grid_chunks, kMaxChunksPerGrid));
  // Each layer of chunks along z is read by one task, on as many cores as the memory budget
  // holds beside the box: a task holds a decoded chunk and its stored bytes or a scratch copy
  // (two chunks' worth), so large chunks under a small budget are read one layer at a time.
  // The error of the first layer that fails is the one thrown, whatever the order the tasks
  // ran in.
  const uint64_t budget = input_limits().max_memory;
  const uint64_t per_task = 2 * uint64_t{array.chunk_bytes};
  const uint64_t room = budget > out.size() ? budget - out.size() : 0;
  const int cores = tbb::this_task_arena::max_concurrency();
  const int tasks = static_cast<int>(std::clamp<uint64_t>(room / std::max<uint64_t>(per_task, 1), 1,
                                                          static_cast<uint64_t>(cores)));
  std::vector<std::exception_ptr> failed(static_cast<size_t>(last.z - first.z + 1));
  const auto read_layers = [&] {
    tbb::parallel_for(first.z, last.z + 1, [&](int64_t kz) {
      try {
        ChunkReader reader(array);
        std::vector<uint8_t> chunk(array.chunk_bytes);
        std::vector<int64_t> at = index;
        for (int64_t ky = first.y; ky <= last.y; ++ky)
          for (int64_t kx = first.x; kx <= last.x; ++kx) {
            at[n - 3] = kz, at[n - 2] = ky, at[n - 1] = kx;
            reader.read(at, chunk);
            // The chunk's part inside the box (edge chunks are stored full-size, past the shape).
            const int64_t z0 = std::max<int64_t>(kz * cz, box.lo.z);
            const int64_t z1 = std::min<int64_t>((kz + 1) * cz, box.hi.z);
            const int64_t y0 = std::max<int64_t>(ky * cy, box.lo.y);
            const int64_t y1 = std::min<int64_t>((ky + 1) * cy, box.hi.y);
            const int64_t x0 = std::max<int64_t>(kx * cx, box.lo.x);
            const int64_t x1 = std::min<int64_t>((kx + 1) * cx, box.hi.x);
            for (int64_t z = z0; z < z1; ++z)
              for (int64_t y = y0; y < y1; ++y) {
                const size_t src = lead_offset + static_cast<size_t>(z - kz * cz) * stride[n - 3] +
                                   static_cast<size_t>(y - ky * cy) * stride[n - 2] +
                                   static_cast<size_t>(x0 - kx * cx);
                const size_t dst =
                    (static_cast<size_t>(z - box.lo.z) * Y + static_cast<size_t>(y - box.lo.y)) *
                        X +
                    static_cast<size_t>(x0 - box.lo.x);
                std::memcpy(out.data() + dst * item, chunk.data() + src * item,
                            static_cast<size_t>(x1 - x0) * item);
              }
          }
      } catch (...) {
        failed[static_cast<size_t>(kz - first.z)] = std::current_exception();
      }
    });
  };
  if (tasks < cores)
    tbb::task_arena(tasks).execute(read_layers);
  else
    read_layers();
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
}

}  // namespace imx::detail
