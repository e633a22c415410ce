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

// Index-space gradients quantized to int16 per component with one scale for the whole volume
// (6 bytes a voxel instead of 12): shading needs the direction, and 1/32767 of the largest
// gradient is far below what Blinn-Phong can show. Depends only on the voxels, not on the TF.
class GradientVolume {
 public:
  GradientVolume() = default;
  // Central differences at voxel centres (one-sided at the borders), in parallel on up to
  // `threads` threads (0 = all).
  explicit GradientVolume(const AnyGrid& voxels, int threads = 0);

  // The gradient at index-space position p, trilinear between the voxel gradients (clamped).
  // Forced inline, and with SSE each corner is one 8-byte load converted in one go: the shading
  // of a semi-transparent volume fetches a gradient for nearly every sample.
  [[gnu::always_inline]] glm::vec3 sample(glm::vec3 p) const {
    glm::vec3 hi = glm::vec3(dims_ - 1);
    p = glm::clamp(p, glm::vec3(0.0f), hi);
    glm::ivec3 i0 = glm::min(glm::ivec3(p), glm::max(dims_ - 2, glm::ivec3(0)));
    glm::vec3 f = p - glm::vec3(i0);
    size_t sy = static_cast<size_t>(dims_.x), sz = sy * dims_.y;
    const int16_t* q = &data_[3 * (i0.z * sz + i0.y * sy + i0.x)];
    // Per axis, the far corner is one voxel on (or none on an axis of one voxel).
    size_t dx = dims_.x > 1 ? 3 : 0, dy = dims_.y > 1 ? 3 * sy : 0, dz = dims_.z > 1 ? 3 * sz : 0;
#if defined(__SSE4_1__)
    // Reads x, y, z and the next voxel's x (ignored): data_ has one spare entry at its end.
    auto g = [&](size_t o) {
      __m128i v = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(q + o));
      return _mm_cvtepi32_ps(_mm_cvtepi16_epi32(v));
    };
    auto mix = [](__m128 a, __m128 b, __m128 t) {
      return _mm_add_ps(a, _mm_mul_ps(t, _mm_sub_ps(b, a)));
    };
    __m128 fx = _mm_set1_ps(f.x), fy = _mm_set1_ps(f.y), fz = _mm_set1_ps(f.z);
    __m128 c0 = mix(mix(g(0), g(dx), fx), mix(g(dy), g(dy + dx), fx), fy);
    __m128 c1 = mix(mix(g(dz), g(dz + dx), fx), mix(g(dz + dy), g(dz + dy + dx), fx), fy);
    alignas(16) float out[4];
    _mm_store_ps(out, _mm_mul_ps(mix(c0, c1, fz), _mm_set1_ps(scale_)));
    return {out[0], out[1], out[2]};
#else
    auto g = [&](size_t o) { return glm::vec3(q[o], q[o + 1], q[o + 2]); };
    glm::vec3 c0 = glm::mix(glm::mix(g(0), g(dx), f.x), glm::mix(g(dy), g(dy + dx), f.x), f.y);
    glm::vec3 c1 =
        glm::mix(glm::mix(g(dz), g(dz + dx), f.x), glm::mix(g(dz + dy), g(dz + dy + dx), f.x), f.y);
    return scale_ * glm::mix(c0, c1, f.z);
#endif
  }

  size_t bytes() const {
    return data_.size() * sizeof(int16_t);
  }
  // The raw layout, for vectorized fetches: x, y, z per voxel (x-fastest), one spare entry after
  // the last voxel, each component times scale() in value units per voxel.
  const int16_t* data() const {
    return data_.data();
  }
  glm::ivec3 dims() const {
    return dims_;
  }
  float scale() const {
    return scale_;
  }

 private:
  std::vector<int16_t> data_;  // x, y, z per voxel, voxels x-fastest, and one spare entry
  glm::ivec3 dims_{1};
  float scale_ = 1.0f;  // int16 unit in value units per voxel
};

}  // namespace imx
