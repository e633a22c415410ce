// GradientVolume: central-difference gradients precomputed at every voxel, sampled trilinearly.
#pragma once
#include <bit>
#include <cstdint>
#include <cstring>
#include <vector>

#include <glm/glm.hpp>

#include "volume/any_grid.hpp"

namespace imx {

// Index-space gradients, quantized with one scale for the whole volume: shading needs the
// direction, and the rounding is far below what Blinn-Phong can show. Two layouts:
//  - packed (4 bytes a voxel): integer voxels whose central differences all fit in 10 bits
//    (any 8-bit volume), stored exactly as 2 x difference, x | y << 10 | z << 20;
//  - int16 (6 bytes a voxel): everything else, in units of 1/32767 of the largest gradient.
// One fetch per corner either way. Depends only on the voxels, not on the TF.
class GradientVolume {
 public:
  GradientVolume() = default;
  // Central differences at voxel centres (one-sided at the borders and beside NaN or inf voxels,
  // no data), in parallel on up to
  // `threads` threads (0 = all).
  explicit GradientVolume(const AnyGrid& voxels, int threads = 0);

  // The gradient at index-space position p, trilinear between the voxel gradients (clamped).
  // Forced inline, each corner four lanes wide (the fourth unused) so that the compiler converts
  // and blends a corner in one vector operation on any target: the shading of a
  // semi-transparent volume fetches a gradient for nearly every sample. Plain code, no
  // intrinsics: it is compiled for whichever target inlines it (docs/architecture.md, "One
  // kernel source").
  [[gnu::always_inline]] glm::vec3 sample(glm::vec3 p) const {
    glm::vec3 hi = glm::vec3(dims_ - 1);
    p = glm::clamp(p, glm::vec3(0.0f), hi);
    glm::ivec3 i0 = glm::min(glm::ivec3(p), glm::max(dims_ - 2, glm::ivec3(0)));
    glm::vec3 f = p - glm::vec3(i0);
    size_t sy = static_cast<size_t>(dims_.x), sz = sy * dims_.y;
    size_t n = i0.z * sz + i0.y * sy + i0.x;
    // Per axis, the far corner is one voxel on (or none on an axis of one voxel).
    size_t dx = dims_.x > 1 ? 1 : 0, dy = dims_.y > 1 ? sy : 0, dz = dims_.z > 1 ? sz : 0;
    if (packed()) {
      const uint32_t* q = &words_[n];
      return trilinear(f, dx, dy, dz, [q](size_t o) { return unpack(q[o]); });
    }
    // Reads x, y, z and the next voxel's x (ignored): data_ has one spare entry at its end.
    const int16_t* q = &data_[3 * n];
    return trilinear(f, 3 * dx, 3 * dy, 3 * dz, [q](size_t o) { return widen(q + o); });
  }

  // The most a GradientVolume of `data` can hold, before it is built: 4 bytes a voxel for 8-bit
  // voxels (always packed), 6 otherwise.
  static uint64_t bytes_at_most(const VolumeData& data);
  size_t bytes() const { return data_.size() * sizeof(int16_t) + words_.size() * sizeof(uint32_t); }
  // Which raw layout holds the gradients, for vectorized fetches. Packed: one word per voxel
  // (x-fastest), each component a signed 10-bit field. Int16: x, y, z per voxel, two spare entries
  // after the last voxel (16 bytes read from any x-neighbour pair stay inside). Either way a stored
  // unit is scale() value units per voxel.
  bool packed() const { return !words_.empty(); }
  const uint32_t* words() const { return words_.data(); }
  const int16_t* data() const { return data_.data(); }
  glm::ivec3 dims() const { return dims_; }
  float scale() const { return scale_; }

 private:
  // A corner's gradient as four lanes (x, y, z and one ignored), blended as a + t (b - a) (the
  // order of the SSE code this replaced, so images keep their bytes). GCC/clang vector types,
  // not intrinsics: the compiler lowers them for whichever target compiles the caller (SSE4,
  // AVX2, NEON; plain loops over the lanes vectorized at half this speed).
  using Corner = float __attribute__((vector_size(16)));
  using Lanes = int32_t __attribute__((vector_size(16)));
  using Bits = uint32_t __attribute__((vector_size(16)));
  using Shorts = int16_t __attribute__((vector_size(16)));
  using Words = uint64_t __attribute__((vector_size(16)));
  static_assert(std::endian::native == std::endian::little, "lane order assumes little endian");
  // Each field shifted to the top of its lane by a multiply (unsigned: it wraps), then down with
  // its sign; lane 3 is garbage.
  static Corner unpack(uint32_t w) {
    const Bits top = Bits{1u << 22, 1u << 12, 1u << 2, 1u} * w;
    return __builtin_convertvector(reinterpret_cast<Lanes>(top) >> 22, Corner);
  }
  // Reads x, y, z and the next entry (ignored: data_ has spare entries at its end): one 8-byte
  // load, each value doubled into a 32-bit lane and shifted down with its sign.
  static Corner widen(const int16_t* q) {
    uint64_t bits;
    std::memcpy(&bits, q, sizeof(bits));
    const Shorts s = reinterpret_cast<Shorts>(Words{bits, 0});
    const Shorts twice = __builtin_shufflevector(s, s, 0, 0, 1, 1, 2, 2, 3, 3);
    return __builtin_convertvector(reinterpret_cast<Lanes>(twice) >> 16, Corner);
  }
  template <class Fetch>
  glm::vec3 trilinear(glm::vec3 f, size_t dx, size_t dy, size_t dz, Fetch g) const {
    // Two statements, as the intrinsics were two calls: clang contracts a product into an FMA
    // only within one expression, GCC (-ffp-contract=fast) either way, so each compiler rounds
    // as it did.
    auto mix = [](Corner a, Corner b, float t) {
      const Corner step = t * (b - a);
      return a + step;
    };
    const Corner c0 = mix(mix(g(0), g(dx), f.x), mix(g(dy), g(dy + dx), f.x), f.y);
    const Corner c1 = mix(mix(g(dz), g(dz + dx), f.x), mix(g(dz + dy), g(dz + dy + dx), f.x), f.y);
    const Corner c = mix(c0, c1, f.z) * scale_;
    return {c[0], c[1], c[2]};
  }

  std::vector<int16_t> data_;    // int16 layout: x, y, z per voxel and two spare entries
  std::vector<uint32_t> words_;  // packed layout
  glm::ivec3 dims_{1};
  float scale_ = 1.0f;  // stored unit in value units per voxel
};

}  // namespace imx
