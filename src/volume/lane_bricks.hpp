// LaneBricks: the empty-space brick walk of BrickDda for eight rays at once, in AVX2 lanes.
#pragma once
#include <cmath>

#include "volume/brick_occupancy.hpp"
#include "volume/lanes.hpp"
#include "volume/volume_acceleration.hpp"

#if IMX_PACKET_LANES
namespace imx::lanes {

// The brick walk of BrickDda in lanes. From each lane's position it finds the first occupied
// brick ahead, jumping over the cube of empty bricks ahead that a brick's distance toward the
// ray's octant vouches for (one brick at a time with SkipMode::bricks), and lands in the brick
// BrickDda::skip lands in: the exit axis steps past the cube's far face, the others take the
// brick at the exit point.
class LaneBricks {
 public:
  LaneBricks(const BrickOccupancy& occ, SkipMode mode)
      : distances_(reinterpret_cast<const int*>(occ.padded_distances())),
        by_distance_(mode == SkipMode::distance) {
    const glm::ivec3 d = occ.grid().dims;
    for (int a = 0; a < 3; ++a) inv_size_[a] = splat(1.0f / static_cast<float>(occ.grid().size[a]));
    stride_y_ = splat(static_cast<float>(d.x));
    stride_z_ = splat(static_cast<float>(d.x) * static_cast<float>(d.y));
    last_[0] = splat(static_cast<float>(d.x - 1));
    last_[1] = splat(static_cast<float>(d.y - 1));
    last_[2] = splat(static_cast<float>(d.z - 1));
  }

  // One ray per lane, in brick units (index space / brick size, same parameter t as the
  // marcher). Axes the ray runs parallel to (|dir| < 1e-12 voxels, as BrickDda) never cross a
  // brick boundary: their inverse direction is infinite and their shift positive.
  struct Rays {
    __m256 origin[3], dir[3];
    __m256 inv_dir[3];   // 1 / dir
    __m256 shift[3];     // crossing brick j's far face at t = (j + shift) * inv_dir
    __m256 toward[3];    // +1, -1 or 0: where the next brick along that axis is
    __m256 backward[3];  // all ones where the ray moves down that axis
    __m256 edge[3];      // the brick after which the ray leaves the grid (-1: never)
    __m256i octant;      // BrickDda::octant(): which of a brick's distances applies
  };

  // The rays of eight origins and directions in index space (structure of arrays, 32-byte
  // aligned).
  Rays load(const float* const origin[3], const float* const dir[3]) const {
    Rays r;
    const __m256 zero = _mm256_setzero_ps(), one = splat(1.0f);
    r.octant = _mm256_setzero_si256();
    for (int a = 0; a < 3; ++a) {
      const __m256 o = _mm256_mul_ps(_mm256_load_ps(origin[a]), inv_size_[a]);
      const __m256 d = _mm256_load_ps(dir[a]);
      const __m256 crosses =
          _mm256_cmp_ps(_mm256_andnot_ps(splat(-0.0f), d), splat(1e-12f), _CMP_GE_OQ);
      const __m256 forward = _mm256_and_ps(crosses, _mm256_cmp_ps(d, zero, _CMP_GT_OQ));
      r.origin[a] = o;
      r.dir[a] = _mm256_mul_ps(d, inv_size_[a]);
      r.backward[a] = _mm256_andnot_ps(forward, crosses);
      r.inv_dir[a] = _mm256_blendv_ps(splat(INFINITY), _mm256_div_ps(one, r.dir[a]), crosses);
      r.shift[a] = _mm256_blendv_ps(one, _mm256_sub_ps(_mm256_and_ps(forward, one), o), crosses);
      r.toward[a] =
          _mm256_or_ps(_mm256_and_ps(forward, one), _mm256_and_ps(r.backward[a], splat(-1.0f)));
      r.edge[a] = _mm256_blendv_ps(splat(-1.0f), _mm256_and_ps(forward, last_[a]), crosses);
      r.octant = _mm256_or_si256(
          r.octant, _mm256_and_si256(_mm256_castps_si256(r.backward[a]), splat(1 << a)));
    }
    return r;
  }

  // Every occupied brick counts (first_occupied's default).
  struct AnyOccupied {
    __m256 operator()(__m256i) const { return _mm256_castsi256_ps(splat(-1)); }
  };

  // Where the lanes in `walk` meet their first occupied brick at or after `t`, before `t1`, that
  // `counts` (lanes of all ones for the brick indices it is given) takes: `enter` gets the time
  // the ray enters it (t itself when it is already in one), `leave` the time it leaves it. An
  // occupied brick it refuses is walked past, one brick at a time. Returns the lanes that meet
  // none.
  template <class Counts = AnyOccupied>
  unsigned first_occupied(const Rays& ray, unsigned walk, __m256 t, __m256 t1, __m256& enter,
                          __m256& leave, Counts counts = {}) const {
    __m256 cell[3];
    for (int a = 0; a < 3; ++a) {
      // As BrickDda's constructor: a start on a boundary belongs to the brick the ray moves into.
      const __m256 x = _mm256_fmadd_ps(t, ray.dir[a], ray.origin[a]);
      const __m256 c = _mm256_blendv_ps(
          _mm256_floor_ps(x), _mm256_sub_ps(_mm256_ceil_ps(x), splat(1.0f)), ray.backward[a]);
      cell[a] = clamp_cell(a, c);
    }
    unsigned none = 0;
    for (unsigned pending = walk; pending;) {
      // Exact in floats: callers keep grids below 2^24 bricks (packet_marching_supported), so
      // the entry index stays below 2^27.
      const __m256i brick = _mm256_cvttps_epi32(
          _mm256_fmadd_ps(cell[2], stride_z_, _mm256_fmadd_ps(cell[1], stride_y_, cell[0])));
      const __m256i index = _mm256_or_si256(_mm256_slli_epi32(brick, 3), ray.octant);
      const __m256i d = _mm256_and_si256(gather_words<1>(distances_, index), splat(0xff));
      const __m256 occupied = _mm256_and_ps(
          _mm256_castsi256_ps(_mm256_cmpeq_epi32(d, _mm256_setzero_si256())), counts(brick));
      // The cube of empty bricks reaches `reach` bricks ahead of this one (with SkipMode::bricks,
      // or for an occupied brick, it is the brick alone).
      __m256 reach = _mm256_setzero_ps();
      if (by_distance_)
        reach = _mm256_cvtepi32_ps(
            _mm256_max_epi32(_mm256_sub_epi32(d, splat(1)), _mm256_setzero_si256()));
      __m256 far[3], exit_t[3];
      for (int a = 0; a < 3; ++a) {
        far[a] = clamp_cell(a, _mm256_fmadd_ps(reach, ray.toward[a], cell[a]));
        exit_t[a] = crossing(ray, a, far[a]);
      }
      const __m256 exit = _mm256_min_ps(_mm256_min_ps(exit_t[0], exit_t[1]), exit_t[2]);
      const __m256 here = lane_mask(pending);
      const __m256 found = _mm256_and_ps(here, occupied);
      enter = _mm256_blendv_ps(enter, t, found);
      leave = _mm256_blendv_ps(leave, exit, found);
      // NaN times end the walk too.
      const __m256 moving = _mm256_andnot_ps(occupied, here);
      const __m256 gone = _mm256_andnot_ps(_mm256_cmp_ps(exit, t1, _CMP_LT_OQ), moving);
      none |= static_cast<unsigned>(_mm256_movemask_ps(gone));
      const __m256 go = _mm256_andnot_ps(gone, moving);
      pending = static_cast<unsigned>(_mm256_movemask_ps(go));
      if (!pending) break;
      // Into the brick beyond the cube: past the far face on the exit axis (ties go to the lowest
      // axis, as in BrickDda), the brick at the exit point (within the cube) on the others.
      __m256 taken = _mm256_setzero_ps();
      for (int a = 0; a < 3; ++a) {
        const __m256 is_exit = _mm256_andnot_ps(taken, _mm256_cmp_ps(exit_t[a], exit, _CMP_EQ_OQ));
        taken = _mm256_or_ps(taken, is_exit);
        const __m256 past = _mm256_add_ps(far[a], ray.toward[a]);
        const __m256 at = _mm256_floor_ps(_mm256_fmadd_ps(exit, ray.dir[a], ray.origin[a]));
        const __m256 inside = _mm256_min_ps(_mm256_max_ps(at, _mm256_min_ps(cell[a], far[a])),
                                            _mm256_max_ps(cell[a], far[a]));
        cell[a] = _mm256_blendv_ps(cell[a], _mm256_blendv_ps(inside, past, is_exit), go);
      }
      t = _mm256_blendv_ps(t, exit, go);
    }
    return none;
  }

 private:
  // Brick c of axis a clamped to the grid (NaN goes to 0, as in BrickDda).
  __m256 clamp_cell(int a, __m256 c) const {
    return _mm256_min_ps(_mm256_max_ps(c, _mm256_setzero_ps()), last_[a]);
  }

  // BrickDda::crossing in lanes: when the ray leaves brick j of axis a, infinity where it never
  // does or where the next brick is outside the grid.
  __m256 crossing(const Rays& ray, int a, __m256 j) const {
    const __m256 t = _mm256_mul_ps(_mm256_add_ps(j, ray.shift[a]), ray.inv_dir[a]);
    return _mm256_blendv_ps(t, splat(INFINITY), _mm256_cmp_ps(j, ray.edge[a], _CMP_EQ_OQ));
  }

  const int* distances_;
  bool by_distance_;
  __m256 inv_size_[3];          // 1 / cells per brick, per axis
  __m256 stride_y_, stride_z_;  // brick index strides, as floats
  __m256 last_[3];              // dims - 1, as floats
};

}  // namespace imx::lanes
#endif  // IMX_PACKET_LANES
