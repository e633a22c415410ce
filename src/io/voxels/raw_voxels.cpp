#include "io/voxels/raw_voxels.hpp"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cstring>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/gzip.hpp"

namespace imx::detail {

static_assert(std::endian::native == std::endian::little,
              "the volume readers and writers assume a little-endian host");

void require_loadable_box(const VoxelBox& box, const std::string& what) {
  if (box.count() > kMaxVoxels)
    throw VolumeTooLarge(fmt::format(
        "{}: {}x{}x{} voxels are more than the {} one volume holds in memory; intermix render "
        "renders such a grid in bricks, and intermix convert -o X.zarr builds its pyramid",
        what, box.hi.x - box.lo.x, box.hi.y - box.lo.y, box.hi.z - box.lo.z, kMaxVoxels));
}

void require_holdable(const VolumeHeader& header, const std::string& what) {
  const VoxelBox whole = VoxelBox::whole(header.dims);
  require_loadable_box(whole, what);
  const size_t bytes = header.type == VoxelType::u8 ? 1 : header.type == VoxelType::f32 ? 4 : 2;
  const uint64_t share = input_limits().max_memory / 2;
  if (whole.count() * bytes > share)
    throw VolumeTooLarge(fmt::format(
        "{}: {}x{}x{} {} voxels ({}) are more than half the memory budget ({}, --max-memory); "
        "intermix render renders such a grid in bricks",
        what, header.dims.x, header.dims.y, header.dims.z, voxel_type_name(header.type),
        format_bytes(whole.count() * bytes), format_bytes(share)));
}

size_t raw_type_size(RawType type) {
  switch (type) {
    case RawType::i8:
    case RawType::u8:
      return 1;
    case RawType::i16:
    case RawType::u16:
      return 2;
    case RawType::i32:
    case RawType::u32:
    case RawType::f32:
      return 4;
    case RawType::i64:
    case RawType::u64:
    case RawType::f64:
      return 8;
  }
  return 1;
}

const char* raw_type_name(RawType type) {
  switch (type) {
    case RawType::i8:
      return "int8";
    case RawType::u8:
      return "uint8";
    case RawType::i16:
      return "int16";
    case RawType::u16:
      return "uint16";
    case RawType::i32:
      return "int32";
    case RawType::u32:
      return "uint32";
    case RawType::i64:
      return "int64";
    case RawType::u64:
      return "uint64";
    case RawType::f32:
      return "float32";
    case RawType::f64:
      return "float64";
  }
  return "unknown";
}

VoxelType storage_type_for(RawType type) {
  switch (type) {
    case RawType::u8:
      return VoxelType::u8;
    case RawType::i8:
    case RawType::i16:
      return VoxelType::i16;
    case RawType::u16:
      return VoxelType::u16;
    default:
      return VoxelType::f32;
  }
}

namespace {

void swap_elements(std::span<uint8_t> bytes, size_t size) {
  if (size == 1) return;
  for (size_t i = 0; i + size <= bytes.size(); i += size) std::reverse(&bytes[i], &bytes[i] + size);
}

template <class Dst>
std::vector<Dst> load_native(size_t count, bool swap_bytes,
                             const std::function<void(std::span<uint8_t>)>& fill) {
  std::vector<Dst> out(count);
  std::span<uint8_t> bytes(reinterpret_cast<uint8_t*>(out.data()), count * sizeof(Dst));
  fill(bytes);
  if (swap_bytes) swap_elements(bytes, sizeof(Dst));
  return out;
}

template <class Src, class Dst>
std::vector<Dst> convert(std::span<const uint8_t> bytes, size_t count) {
  std::vector<Dst> out(count);
  for (size_t i = 0; i < count; ++i) {
    Src v;
    std::memcpy(&v, bytes.data() + i * sizeof(Src), sizeof(Src));
    if constexpr (std::is_same_v<Src, double>)  // out-of-range double -> float is undefined
      v = std::clamp(v, -double{FLT_MAX}, double{FLT_MAX});
    out[i] = static_cast<Dst>(v);
  }
  return out;
}

}  // namespace

VoxelStorage load_voxels(RawType type, size_t count, bool swap_bytes, const std::string& what,
                         const std::function<void(std::span<uint8_t>)>& fill) {
  const bool native =
      type == RawType::u8 || type == RawType::i16 || type == RawType::u16 || type == RawType::f32;
  const size_t stored_size = storage_type_for(type) == VoxelType::f32 ? 4 : 2;
  // A converted type holds the file's bytes and the converted voxels at once.
  check_memory(count * raw_type_size(type) + (native ? 0 : count * stored_size),
               fmt::format("{}: {} voxels of {}", what, count, raw_type_name(type)));
  switch (type) {
    case RawType::u8:
      return load_native<uint8_t>(count, false, fill);
    case RawType::i16:
      return load_native<int16_t>(count, swap_bytes, fill);
    case RawType::u16:
      return load_native<uint16_t>(count, swap_bytes, fill);
    case RawType::f32:
      return load_native<float>(count, swap_bytes, fill);
    default:
      break;
  }
  std::vector<uint8_t> bytes(count * raw_type_size(type));
  fill(bytes);
  if (swap_bytes) swap_elements(bytes, raw_type_size(type));
  switch (type) {
    case RawType::i8:
      return convert<int8_t, int16_t>(bytes, count);
    case RawType::i32:
      return convert<int32_t, float>(bytes, count);
    case RawType::u32:
      return convert<uint32_t, float>(bytes, count);
    case RawType::i64:
      return convert<int64_t, float>(bytes, count);
    case RawType::u64:
      return convert<uint64_t, float>(bytes, count);
    default:
      return convert<double, float>(bytes, count);
  }
}

void for_each_box_run(glm::ivec3 dims, const VoxelBox& box, size_t element_size,
                      const std::function<void(uint64_t, size_t)>& run) {
  const size_t row = static_cast<size_t>(box.hi.x - box.lo.x) * element_size;
  uint64_t start = 0;
  size_t length = 0;
  for (int k = box.lo.z; k < box.hi.z; ++k)
    for (int j = box.lo.y; j < box.hi.y; ++j) {
      const uint64_t offset =
          ((static_cast<uint64_t>(k) * static_cast<uint64_t>(dims.y) + static_cast<uint64_t>(j)) *
               static_cast<uint64_t>(dims.x) +
           static_cast<uint64_t>(box.lo.x)) *
          element_size;
      if (length > 0 && offset == start + length) {
        length += row;
        continue;
      }
      if (length > 0) run(start, length);
      start = offset;
      length = row;
    }
  if (length > 0) run(start, length);
}

VoxelStorage load_voxels_region(RawType type, glm::ivec3 dims, const VoxelBox& box, bool swap_bytes,
                                const std::string& what,
                                const std::function<void(uint64_t, std::span<uint8_t>)>& fill) {
  return load_voxels(type, box.count(), swap_bytes, what, [&](std::span<uint8_t> bytes) {
    size_t at = 0;
    for_each_box_run(dims, box, raw_type_size(type), [&](uint64_t offset, size_t length) {
      fill(offset, bytes.subspan(at, length));
      at += length;
    });
  });
}

VoxelStorage load_raw_voxels(std::istream& in, uint64_t start, RawType type, glm::ivec3 dims,
                             const VoxelBox& box, bool swap_bytes, const std::string& what) {
  return load_voxels_region(
      type, dims, box, swap_bytes, what, [&](uint64_t offset, std::span<uint8_t> bytes) {
        in.clear();
        in.seekg(static_cast<std::streamoff>(start + offset));
        in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
        if (static_cast<size_t>(in.gcount()) != bytes.size())
          throw Error(fmt::format("{}: expected {} bytes of voxel data at byte {}, found {}", what,
                                  bytes.size(), start + offset, in.gcount()));
      });
}

VoxelStorage load_gzip_voxels(std::istream& in, size_t skip, RawType type, glm::ivec3 dims,
                              const VoxelBox& box, bool swap_bytes, const std::string& what) {
  const size_t count = static_cast<size_t>(dims.x) * dims.y * dims.z;
  const size_t total = count * raw_type_size(type);
  auto short_data = [&](size_t found) {
    return Error(
        fmt::format("{}: expected {} bytes of voxel data ({} x {}) after "
                    "decompression, found {} (truncated file?)",
                    what, total, count, raw_type_name(type), found));
  };
  GzipStream stream(in, what);
  // Inflated bytes so far, counted from the start of the voxels (after `skip`).
  uint64_t at = 0;
  bool skipped = false;
  // Drops the inflated bytes up to voxel byte `offset`.
  auto advance = [&](uint64_t offset) {
    if (!skipped) {
      if (stream.skip(skip) < skip) throw short_data(0);
      skipped = true;
    }
    if (offset > at) {
      const size_t got = stream.skip(static_cast<size_t>(offset - at));
      at += got;
      if (at < offset) throw short_data(static_cast<size_t>(at));
    }
  };
  VoxelStorage voxels = load_voxels_region(type, dims, box, swap_bytes, what,
                                           [&](uint64_t offset, std::span<uint8_t> bytes) {
                                             advance(offset);
                                             const size_t got = stream.read(bytes);
                                             at += got;
                                             if (got < bytes.size())
                                               throw short_data(static_cast<size_t>(at));
                                           });
  advance(total);
  stream.finish(total);
  return voxels;
}

}  // namespace imx::detail
