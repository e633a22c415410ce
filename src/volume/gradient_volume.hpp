// GradientVolume: central-difference gradients precomputed at every voxel, sampled trilinearly.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#if defined(__SSE4_1__)
#include <immintrin.h>
#endif

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
  // Forced inline, and with SSE each corner is converted in one go: the shading of a
  // semi-transparent volume fetches a gradient for nearly every sample.
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
#if defined(__SSE4_1__)
  using Corner = __m128;
  static Corner unpack(uint32_t w) {
#if defined(__AVX2__)
    const __m128i v =
        _mm_sllv_epi32(_mm_set1_epi32(static_cast<int>(w)), _mm_setr_epi32(22, 12, 2, 0));
    return _mm_cvtepi32_ps(_mm_srai_epi32(v, 22));
#else
    return _mm_cvtepi32_ps(_mm_setr_epi32(field(w, 0), field(w, 1), field(w, 2), 0));
#endif
  }
  static Corner widen(const int16_t* q) {
    __m128i v = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(q));
    return _mm_cvtepi32_ps(_mm_cvtepi16_epi32(v));
  }
  template <class Fetch>
  glm::vec3 trilinear(glm::vec3 f, size_t dx, size_t dy, size_t dz, Fetch g) const {
    auto mix = [](__m128 a, __m128 b, __m128 t) {
      return _mm_add_ps(a, _mm_mul_ps(t, _mm_sub_ps(b, a)));
    };
    __m128 fx = _mm_set1_ps(f.x), fy = _mm_set1_ps(f.y), fz = _mm_set1_ps(f.z);
    __m128 c0 = mix(mix(g(0), g(dx), fx), mix(g(dy), g(dy + dx), fx), fy);
    __m128 c1 = mix(mix(g(dz), g(dz + dx), fx), mix(g(dz + dy), g(dz + dy + dx), fx), fy);
    alignas(16) float out[4];
    _mm_store_ps(out, _mm_mul_ps(mix(c0, c1, fz), _mm_set1_ps(scale_)));
    return {out[0], out[1], out[2]};
  }
#else
  using Corner = glm::vec3;
  static Corner unpack(uint32_t w) {
    return glm::vec3(field(w, 0), field(w, 1), field(w, 2));
  }
  static Corner widen(const int16_t* q) {
    return glm::vec3(q[0], q[1], q[2]);
  }
  template <class Fetch>
  glm::vec3 trilinear(glm::vec3 f, size_t dx, size_t dy, size_t dz, Fetch g) const {
    glm::vec3 c0 = glm::mix(glm::mix(g(0), g(dx), f.x), glm::mix(g(dy), g(dy + dx), f.x), f.y);
    glm::vec3 c1 =
        glm::mix(glm::mix(g(dz), g(dz + dx), f.x), glm::mix(g(dz + dy), g(dz + dy + dx), f.x), f.y);
    return scale_ * glm::mix(c0, c1, f.z);
  }
#endif
  // Signed 10-bit field a (0 = x, 1 = y, 2 = z) of a packed word.
  static int field(uint32_t w, int a) {
    return static_cast<int32_t>(w << (22 - 10 * a)) >> 22;
  }

  std::vector<int16_t> data_;    // int16 layout: x, y, z per voxel and two spare entries
  std::vector<uint32_t> words_;  // packed layout
  glm::ivec3 dims_{1};
  float scale_ = 1.0f;  // stored unit in value units per voxel
};

}  // namespace imx
