// LaneGrid: trilinear voxel fetches for eight rays at once in AVX2 lanes, as VoxelGrid<T>::sample.
#pragma once
#include <type_traits>

#include "volume/lanes.hpp"
#include "volume/voxel_grid.hpp"

#if IMX_PACKET_LANES
namespace imx::lanes {

// Where trilinear fetches read in a grid of `dims` voxels: the lower corner's voxel index and
// the fractions toward the upper one, clamped as VoxelGrid<T>::sample clamps.
class LaneLattice {
 public:
  explicit LaneLattice(glm::ivec3 dims)
      : hi_x_(splat(static_cast<float>(dims.x - 1))),
        hi_y_(splat(static_cast<float>(dims.y - 1))),
        hi_z_(splat(static_cast<float>(dims.z - 1))),
        max_x_(splat(dims.x - 2)),
        max_y_(splat(dims.y - 2)),
        max_z_(splat(dims.z - 2)),
        sy_(splat(dims.x)),
        sz_(splat(dims.x * dims.y)) {}

  __m256i sy() const { return sy_; }
  __m256i sz() const { return sz_; }

  __m256i locate(__m256 px, __m256 py, __m256 pz, __m256& fx, __m256& fy, __m256& fz) const {
    const __m256 zero = _mm256_setzero_ps();
    // max(p, 0) returns 0 for a NaN p, as the clamp must to stay inside the grid.
    px = _mm256_min_ps(_mm256_max_ps(px, zero), hi_x_);
    py = _mm256_min_ps(_mm256_max_ps(py, zero), hi_y_);
    pz = _mm256_min_ps(_mm256_max_ps(pz, zero), hi_z_);
    __m256i ix = _mm256_min_epi32(_mm256_cvttps_epi32(px), max_x_);
    __m256i iy = _mm256_min_epi32(_mm256_cvttps_epi32(py), max_y_);
    __m256i iz = _mm256_min_epi32(_mm256_cvttps_epi32(pz), max_z_);
    fx = _mm256_sub_ps(px, _mm256_cvtepi32_ps(ix));
    fy = _mm256_sub_ps(py, _mm256_cvtepi32_ps(iy));
    fz = _mm256_sub_ps(pz, _mm256_cvtepi32_ps(iz));
    return _mm256_add_epi32(
        ix, _mm256_add_epi32(_mm256_mullo_epi32(iy, sy_), _mm256_mullo_epi32(iz, sz_)));
  }

 private:
  __m256 hi_x_, hi_y_, hi_z_;      // dims - 1: the clamp
  __m256i max_x_, max_y_, max_z_;  // dims - 2: the last lower corner
  __m256i sy_, sz_;                // strides in voxels
};

// VoxelGrid<T>::sample in lanes. 8- and 16-bit voxels are fetched as 32-bit words holding the
// x-neighbours (i, i + 1) together: four gathers instead of eight. A word read at the last
// u8 voxel pair would run past the voxels, so that one is read from at most N - 4 and shifted.
template <class T>
class LaneGrid {
 public:
  explicit LaneGrid(const VoxelGrid<T>& g)
      : data_(g.data), lattice_(g.dims), last_word_(splat(g.dims.x * g.dims.y * g.dims.z - 4)) {}

  __m256 sample(__m256 px, __m256 py, __m256 pz) const {
    __m256 fx, fy, fz;
    const __m256i base = lattice_.locate(px, py, pz, fx, fy, fz);
    const __m256i sy = lattice_.sy(), sz = lattice_.sz();
    __m256i o01 = _mm256_add_epi32(base, sy), o10 = _mm256_add_epi32(base, sz);
    __m256i o11 = _mm256_add_epi32(o01, sz);
    __m256 c[8];  // c000, c100, c010, c110, c001, c101, c011, c111
    if constexpr (std::is_same_v<T, float>) {
      const __m256i one = splat(1);
      const __m256i offs[4] = {base, o01, o10, o11};
      for (int k = 0; k < 4; ++k) {
        c[2 * k] = gather_floats(data_, offs[k]);
        c[2 * k + 1] = gather_floats(data_, _mm256_add_epi32(offs[k], one));
      }
    } else {
      __m256i w[4];
      if constexpr (sizeof(T) == 1) {
        w[0] = gather_words<1>(data_, base);
        w[1] = gather_words<1>(data_, o01);
        w[2] = gather_words<1>(data_, o10);
        // Only the last pair can lie within the last 3 bytes (every stride is at least 2).
        __m256i at = _mm256_min_epi32(o11, last_word_);
        __m256i shift = _mm256_slli_epi32(_mm256_sub_epi32(o11, at), 3);
        w[3] = _mm256_srlv_epi32(gather_words<1>(data_, at), shift);
        const __m256i byte = splat(0xff);
        for (int k = 0; k < 4; ++k) {
          c[2 * k] = _mm256_cvtepi32_ps(_mm256_and_si256(w[k], byte));
          c[2 * k + 1] = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(w[k], 8), byte));
        }
      } else {
        // Element i + 1 is at most the last voxel: no word runs past the end.
        w[0] = gather_words<2>(data_, base);
        w[1] = gather_words<2>(data_, o01);
        w[2] = gather_words<2>(data_, o10);
        w[3] = gather_words<2>(data_, o11);
        for (int k = 0; k < 4; ++k) {
          if constexpr (std::is_signed_v<T>) {
            c[2 * k] = _mm256_cvtepi32_ps(_mm256_srai_epi32(_mm256_slli_epi32(w[k], 16), 16));
            c[2 * k + 1] = _mm256_cvtepi32_ps(_mm256_srai_epi32(w[k], 16));
          } else {
            c[2 * k] = _mm256_cvtepi32_ps(_mm256_and_si256(w[k], splat(0xffff)));
            c[2 * k + 1] = _mm256_cvtepi32_ps(_mm256_srli_epi32(w[k], 16));
          }
        }
      }
    }
    __m256 c00 = lerp(c[0], c[1], fx), c10 = lerp(c[2], c[3], fx);
    __m256 c01 = lerp(c[4], c[5], fx), c11 = lerp(c[6], c[7], fx);
    return lerp(lerp(c00, c10, fy), lerp(c01, c11, fy), fz);
  }

 private:
  const T* data_;
  LaneLattice lattice_;
  __m256i last_word_;  // the last voxel a 32-bit word may start at
};

}  // namespace imx::lanes
#endif  // IMX_PACKET_LANES
