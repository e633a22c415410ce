// Lane helpers for the AVX2 ray packets: eight floats per register, one ray per lane.
#pragma once

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>

#include <cfloat>
#define IMX_PACKET_LANES 1
#else
#define IMX_PACKET_LANES 0
#endif

#if IMX_PACKET_LANES
namespace imx::lanes {

constexpr int kLanes = 8;
constexpr unsigned kAllLanes = (1u << kLanes) - 1;

inline __m256 splat(float x) {
  return _mm256_set1_ps(x);
}
inline __m256i splat(int x) {
  return _mm256_set1_epi32(x);
}

// All ones in the lanes whose bit is set in `bits`.
inline __m256 lane_mask(unsigned bits) {
  const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  return _mm256_castsi256_ps(
      _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(bits)), bit), bit));
}

inline __m256 dot3(__m256 ax, __m256 ay, __m256 az, __m256 bx, __m256 by, __m256 bz) {
  return _mm256_fmadd_ps(az, bz, _mm256_fmadd_ps(ay, by, _mm256_mul_ps(ax, bx)));
}

// a + f * (b - a), the interpolation step of every trilinear and bilinear fetch.
inline __m256 lerp(__m256 a, __m256 b, __m256 f) {
  return _mm256_fmadd_ps(f, _mm256_sub_ps(b, a), a);
}

// no_data() in lanes: all ones where s is NaN or infinite.
inline __m256 no_data_lanes(__m256 s) {
  return _mm256_cmp_ps(_mm256_andnot_ps(splat(-0.0f), s), splat(FLT_MAX), _CMP_NLE_UQ);
}

}  // namespace imx::lanes
#endif  // IMX_PACKET_LANES
