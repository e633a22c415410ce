#include "io/raw_voxels.hpp"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cstring>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/gzip.hpp"

namespace imx::detail {

static_assert(std::endian::native == std::endian::little,
              "the volume readers and writers assume a little-endian host");

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

VoxelStorage load_gzip_voxels(std::istream& in, size_t skip, RawType type, size_t count,
                              bool swap_bytes, const std::string& what) {
  return load_voxels(type, count, swap_bytes, what, [&](std::span<uint8_t> bytes) {
    size_t found = gunzip(in, skip, bytes, what);
    if (found != bytes.size())
      throw Error(
          fmt::format("{}: expected {} bytes of voxel data ({} x {}) after "
                      "decompression, found {} (truncated file?)",
                      what, bytes.size(), count, raw_type_name(type), found));
  });
}

}  // namespace imx::detail
