// ZT-buffer storage: per sample a fixed array of N packed slabs, 12 B (RGBA8) or 24 B (RGBA32F)
// each (SPEC §4). Unused slots carry a negative thickness, so no per-pixel count is stored.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "slab/slab.hpp"

namespace imx {

enum class SlabFormat : uint8_t { rgba32f, rgba8 };

// 24 bytes: the slab as the kernels use it.
struct PackedSlab32 {
  float t_back;
  float thickness;  // < 0: unused slot
  glm::vec4 color;  // premultiplied
};

// 12 bytes: opacity and the straight (medium) colour in 8 bits each; straight colour keeps its
// precision for faint slabs, where premultiplied 8-bit values would round to nothing.
struct PackedSlab8 {
  float t_back;
  float thickness;  // < 0: unused slot
  uint8_t rgba[4];
};

static_assert(sizeof(PackedSlab32) == 24 && sizeof(PackedSlab8) == 12);

inline constexpr int slab_bytes(SlabFormat f) {
  return f == SlabFormat::rgba8 ? 12 : 24;
}

inline PackedSlab32 pack32(const Slab& s) {
  return {s.t_back, s.thickness, s.color};
}
inline Slab unpack(const PackedSlab32& p) {
  return {p.t_back, p.thickness, p.color};
}

inline uint8_t to_u8(float v) {
  return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

inline PackedSlab8 pack8(const Slab& s) {
  float a = s.color.a;
  float inv = a > 0.0f ? 1.0f / a : 0.0f;
  return {s.t_back,
          s.thickness,
          {to_u8(s.color.r * inv), to_u8(s.color.g * inv), to_u8(s.color.b * inv), to_u8(a)}};
}

inline Slab unpack(const PackedSlab8& p) {
  float a = p.rgba[3] / 255.0f;
  glm::vec4 c(p.rgba[0] / 255.0f * a, p.rgba[1] / 255.0f * a, p.rgba[2] / 255.0f * a, a);
  return {p.t_back, p.thickness, c};
}

// A packed slab of either format from its bytes (as ZtBuffer::slots holds them).
inline Slab unpack_bytes(const std::byte* bytes, SlabFormat format) {
  if (format == SlabFormat::rgba8) {
    PackedSlab8 p;
    std::memcpy(&p, bytes, sizeof p);
    return unpack(p);
  }
  PackedSlab32 p;
  std::memcpy(&p, bytes, sizeof p);
  return unpack(p);
}

// A buffer of `samples` slab arrays of `capacity` slabs each, in one of the two formats.
class ZtBuffer {
 public:
  ZtBuffer() = default;
  ZtBuffer(size_t samples, int capacity, SlabFormat format) { reset(samples, capacity, format); }

  // Resizes (keeping the allocation where it can) and empties every array.
  void reset(size_t samples, int capacity, SlabFormat format) {
    samples_ = samples;
    capacity_ = capacity;
    format_ = format;
    size_t n = samples * static_cast<size_t>(capacity);
    if (format == SlabFormat::rgba8) {
      s8_.assign(n, PackedSlab8{0.0f, -1.0f, {0, 0, 0, 0}});
      s32_.clear();
    } else {
      s32_.assign(n, PackedSlab32{0.0f, -1.0f, glm::vec4(0.0f)});
      s8_.clear();
    }
  }

  // Copies the array of `sample` into `out` (room for capacity() slabs); returns its length.
  int load(size_t sample, std::span<Slab> out) const {
    size_t base = sample * static_cast<size_t>(capacity_);
    int n = std::min(capacity_, static_cast<int>(out.size()));
    int k = 0;
    if (format_ == SlabFormat::rgba8)
      for (; k < n && s8_[base + k].thickness >= 0.0f; ++k) out[k] = unpack(s8_[base + k]);
    else
      for (; k < n && s32_[base + k].thickness >= 0.0f; ++k) out[k] = unpack(s32_[base + k]);
    return k;
  }

  // Stores `slabs` (at most capacity(); the rest is dropped) as the array of `sample`.
  void store(size_t sample, std::span<const Slab> slabs) {
    size_t base = sample * static_cast<size_t>(capacity_);
    int n = std::min(capacity_, static_cast<int>(slabs.size()));
    // A stored thickness is never negative: the sentinel (-1) marks the end.
    const Slab end{0.0f, -1.0f, glm::vec4(0.0f)};
    auto stored = [&](int k) {
      Slab s = slabs[k];
      s.thickness = std::max(s.thickness, 0.0f);
      return s;
    };
    if (format_ == SlabFormat::rgba8) {
      for (int k = 0; k < n; ++k) s8_[base + k] = pack8(stored(k));
      for (int k = n; k < capacity_; ++k) s8_[base + k] = pack8(end);
    } else {
      for (int k = 0; k < n; ++k) s32_[base + k] = pack32(stored(k));
      for (int k = n; k < capacity_; ++k) s32_[base + k] = pack32(end);
    }
  }

  // Copies the array of `sample` of `from` (same capacity and format) into this buffer.
  void copy(size_t sample, const ZtBuffer& from, size_t from_sample) {
    size_t a = sample * static_cast<size_t>(capacity_);
    size_t b = from_sample * static_cast<size_t>(capacity_);
    if (format_ == SlabFormat::rgba8)
      std::copy_n(from.s8_.begin() + b, capacity_, s8_.begin() + a);
    else
      std::copy_n(from.s32_.begin() + b, capacity_, s32_.begin() + a);
  }

  // The length of the array of `sample` (its slots up to the first unused one).
  int count(size_t sample) const {
    size_t base = sample * static_cast<size_t>(capacity_);
    int k = 0;
    if (format_ == SlabFormat::rgba8)
      while (k < capacity_ && s8_[base + k].thickness >= 0.0f) ++k;
    else
      while (k < capacity_ && s32_[base + k].thickness >= 0.0f) ++k;
    return k;
  }

  // The packed slots of `sample` (capacity() slabs of slab_bytes(format()) bytes), as stored:
  // what a message carries, so slabs cross processes bit for bit.
  const std::byte* slots(size_t sample) const {
    size_t base = sample * static_cast<size_t>(capacity_);
    return format_ == SlabFormat::rgba8 ? reinterpret_cast<const std::byte*>(s8_.data() + base)
                                        : reinterpret_cast<const std::byte*>(s32_.data() + base);
  }

  size_t samples() const { return samples_; }
  int capacity() const { return capacity_; }
  SlabFormat format() const { return format_; }
  size_t bytes() const {
    return s8_.size() * sizeof(PackedSlab8) + s32_.size() * sizeof(PackedSlab32);
  }

 private:
  size_t samples_ = 0;
  int capacity_ = 0;
  SlabFormat format_ = SlabFormat::rgba32f;
  std::vector<PackedSlab8> s8_;
  std::vector<PackedSlab32> s32_;
};

}  // namespace imx
