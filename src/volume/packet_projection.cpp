#include "volume/packet_projection.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <type_traits>

#include "volume/iso_crossing.hpp"
#include "volume/lane_bricks.hpp"
#include "volume/lane_grid.hpp"
#include "volume/lane_kernel.hpp"
#include "volume/projection.hpp"

namespace imx {
namespace {

VolumeHit walk_one(const PreparedVolume& v, const PacketRay& r, float step, int bisections,
                   std::span<const ShadingLight> lights, bool& found) {
  VolumeHit hit;
  const KeptSpan whole(RayInterval{r.t0, r.t1});
  found = v.object->style == VolumeStyle::iso
              ? find_iso_crossing(v, r.ray, whole, step, bisections, lights, hit)
              : project_volume(v, r.ray, whole, step, hit);
  return hit;
}

// The reference: the scalar walk per ray.
void project_each(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                  int bisections, std::span<const ShadingLight> lights, std::span<glm::vec4> out) {
  for (size_t i = 0; i < rays.size(); ++i) {
    bool found = false;
    const VolumeHit hit = walk_one(v, rays[i], step, bisections, lights, found);
    out[i] = found ? hit.color : glm::vec4(0.0f);
  }
}

#if IMX_PACKET_LANES

using namespace lanes;

enum class Mode : uint8_t { max, min, integral, iso };

constexpr int kMaxLookDelay = 4;     // points a lane that entered a new brick may walk unjudged
constexpr int kMaxLookBackoff = 64;  // the most points between looks after fruitless ones

// The per-lane state, structure of arrays so that a step loads whole vectors.
struct alignas(32) ProjectionLanes {
  float ox[kLanes], oy[kLanes], oz[kLanes];  // the ray in index space, same parameter t
  float dx[kLanes], dy[kLanes], dz[kLanes];
  float inv_d[3][kLanes];       // 1 / d per axis, NaN where the ray runs parallel
  float t[kLanes];              // the last point sampled
  float t1[kLanes];             // where the span ends
  float next_cell[kLanes];      // the next point is next_cell * step (or t1)
  float checked_until[kLanes];  // the brick verdict of the last look holds up to here
  float best[kLanes];           // max / min: the running value; iso: value - iso at t
  float best_t[kLanes];         // max / min: where it was first seen
  float cross_t[kLanes];        // iso: the point after the sign change
  float cross_f[kLanes];        //   and value - iso there
  int32_t found[kLanes];        // iso: a sign change was seen
  float sum[4][kLanes];         // integral: (mu r, mu g, mu b, mu) integrated
  float prev[4][kLanes];        //   and at t
};

// With NoData: a volume whose NaN or inf voxels are no data (float only; others never test).
template <class T, bool NoData = false>
class ProjectionKernel {
 public:
  ProjectionKernel(const PreparedVolume& v, const VoxelGrid<T>& grid,
                   std::span<const PacketRay> rays, float step, int bisections,
                   std::span<const ShadingLight> lights, std::span<glm::vec4> out)
      : v_(v),
        grid_(grid),
        rays_(rays),
        out_(out),
        lights_(lights),
        step_(step),
        bisections_(bisections),
        iso_(static_cast<float>(v.object->iso_value)) {
    const VolumeStyle s = v.object->style;
    mode_ = s == VolumeStyle::mip     ? Mode::max
            : s == VolumeStyle::minip ? Mode::min
            : s == VolumeStyle::iso   ? Mode::iso
                                      : Mode::integral;
    const BrickMinMax* r = skip_ranges(v);
    if (r) {
      ranges_ = reinterpret_cast<const float*>(r->ranges().data());
      const BrickGrid& g = r->grid();
      for (int a = 0; a < 3; ++a) {
        brick_size_[a] = static_cast<float>(g.size[a]);
        inv_brick_size_[a] = 1.0f / brick_size_[a];
        brick_last_[a] = static_cast<float>(g.dims[a] - 1);
        voxel_last_[a] = static_cast<float>(g.voxel_dims[a] - 1);
      }
      brick_stride_y_ = g.dims.x;
      brick_stride_z_ = g.dims.x * g.dims.y;
      // The TF's empty bricks hold nothing that changes the result: walk past them as DVR does.
      const bool empty_skips = mode_ == Mode::max   ? v.limits.invisible_only_below
                               : mode_ == Mode::min ? v.limits.invisible_only_above
                                                    : true;
      if (empty_skips && v.accel.occupancy) bricks_.emplace(*v.accel.occupancy, v.accel.skip);
    }
  }

  void run() {
    for (size_t first = 0; first < rays_.size(); first += kLanes) {
      const int n = static_cast<int>(std::min<size_t>(kLanes, rays_.size() - first));
      unsigned live = start(first, n);
      while (live) live = advance(live);
      finish(first, n);
    }
  }

 private:
  // Puts the rays first .. first + n - 1 into lanes (idle lanes repeat the last one) and takes
  // their first point, t0; returns the lanes with more to walk.
  unsigned start(size_t first, int n) {
    unsigned live = 0;
    for (int l = 0; l < kLanes; ++l) {
      const PacketRay& pr = rays_[first + static_cast<size_t>(std::min(l, n - 1))];
      const glm::vec3 o = v_.to_index(pr.ray.origin);
      const glm::vec3 d = glm::mat3(v_.world_to_index) * pr.ray.dir;
      L_.ox[l] = o.x, L_.oy[l] = o.y, L_.oz[l] = o.z;
      L_.dx[l] = d.x, L_.dy[l] = d.y, L_.dz[l] = d.z;
      for (int a = 0; a < 3; ++a)  // as RangeBricks: an axis the ray runs along is never left
        L_.inv_d[a][l] = std::abs(d[a]) < 1e-12f ? NAN : 1.0f / d[a];
      L_.t[l] = pr.t0;
      L_.t1[l] = pr.t1;
      L_.next_cell[l] = static_cast<float>(grid_cell(pr.t0, step_) + 1.0);
      L_.checked_until[l] = -INFINITY;
      L_.best[l] = mode_ == Mode::max ? v_.limits.invisible_up_to : v_.limits.invisible_from;
      L_.best_t[l] = pr.t0;
      L_.found[l] = 0;
      for (int c = 0; c < 4; ++c) L_.sum[c][l] = L_.prev[c][l] = 0.0f;
      if (l < n && pr.t1 > pr.t0) live |= 1u << l;
    }
    if (bricks_) {
      const float* const origin[3] = {L_.ox, L_.oy, L_.oz};
      const float* const dir[3] = {L_.dx, L_.dy, L_.dz};
      brick_rays_ = bricks_->load(origin, dir);
    }
    const __m256 t = _mm256_load_ps(L_.t);
    live &= ~update(live, sample_at(t), t, true);
    look_delay_ = kMaxLookDelay;  // every lane looks at its first brick at once
    look_limit_ = kMaxLookDelay;
    return look(live);
  }

  // The next point in every live lane; returns the lanes still walking.
  unsigned advance(unsigned live) {
    const __m256 active = lane_mask(live);
    const __m256 t1 = _mm256_load_ps(L_.t1), next_cell = _mm256_load_ps(L_.next_cell);
    const __m256 b = _mm256_min_ps(t1, _mm256_mul_ps(next_cell, splat(step_)));
    unsigned done = update(live, sample_at(b), b, false);
    _mm256_store_ps(L_.next_cell,
                    _mm256_blendv_ps(next_cell, _mm256_add_ps(next_cell, splat(1.0f)), active));
    done |= static_cast<unsigned>(
        _mm256_movemask_ps(_mm256_and_ps(active, _mm256_cmp_ps(b, t1, _CMP_GE_OQ))));
    return look(live & ~done);
  }

  __m256 sample_at(__m256 t) const {
    return grid_.sample(_mm256_fmadd_ps(t, _mm256_load_ps(L_.dx), _mm256_load_ps(L_.ox)),
                        _mm256_fmadd_ps(t, _mm256_load_ps(L_.dy), _mm256_load_ps(L_.oy)),
                        _mm256_fmadd_ps(t, _mm256_load_ps(L_.dz), _mm256_load_ps(L_.oz)));
  }

  // Takes the value s at point `at` in the lanes of `live`; returns those that are done (the TF
  // saturated, or a sign change found).
  unsigned update(unsigned live, __m256 s, __m256 at, bool first) {
    const __m256 active = lane_mask(live);
    const __m256 t = _mm256_load_ps(L_.t);
    __m256 done = _mm256_setzero_ps();
    __m256 moved = active;  // lanes whose last point becomes `at`
    if (mode_ == Mode::max || mode_ == Mode::min) {
      const __m256 best = _mm256_load_ps(L_.best);
      const bool max = mode_ == Mode::max;
      // The predicate must be a constant: one compare per mode.
      const __m256 beats =
          max ? _mm256_cmp_ps(s, best, _CMP_GT_OQ) : _mm256_cmp_ps(s, best, _CMP_LT_OQ);
      __m256 better = _mm256_and_ps(active, beats);
      if constexpr (NoData)
        better = _mm256_andnot_ps(no_data_lanes(s), better);  // never the max or min
      const __m256 nbest = _mm256_blendv_ps(best, s, better);
      _mm256_store_ps(L_.best, nbest);
      _mm256_store_ps(L_.best_t, _mm256_blendv_ps(_mm256_load_ps(L_.best_t), at, better));
      done = max ? _mm256_cmp_ps(nbest, splat(v_.limits.constant_from), _CMP_GE_OQ)
                 : _mm256_cmp_ps(nbest, splat(v_.limits.constant_up_to), _CMP_LE_OQ);
    } else if (mode_ == Mode::iso) {
      const __m256 f = _mm256_sub_ps(s, splat(iso_));
      const __m256 fa = _mm256_load_ps(L_.best);
      if (!first) {
        const __m256 zero = _mm256_setzero_ps();
        done =
            _mm256_xor_ps(_mm256_cmp_ps(fa, zero, _CMP_LT_OQ), _mm256_cmp_ps(f, zero, _CMP_LT_OQ));
        done = _mm256_and_ps(done, active);
        // A crossing lies between two samples of data (find_iso_crossing).
        if constexpr (NoData)
          done = _mm256_andnot_ps(_mm256_or_ps(no_data_lanes(f), no_data_lanes(fa)), done);
        _mm256_store_ps(L_.cross_t, _mm256_blendv_ps(_mm256_load_ps(L_.cross_t), at, done));
        _mm256_store_ps(L_.cross_f, _mm256_blendv_ps(_mm256_load_ps(L_.cross_f), f, done));
        const __m256i found = _mm256_load_si256(reinterpret_cast<const __m256i*>(L_.found));
        _mm256_store_si256(reinterpret_cast<__m256i*>(L_.found),
                           _mm256_or_si256(found, _mm256_castps_si256(done)));
        moved = _mm256_andnot_ps(done, active);  // the bracket starts at t: keep it
      }
      _mm256_store_ps(L_.best, _mm256_blendv_ps(fa, f, moved));
    } else {
      __m256 e[4];
      attenuation(s, e);
      if constexpr (NoData) {  // no attenuation, as a value of opacity 0
        const __m256 none = no_data_lanes(s);
        for (int c = 0; c < 4; ++c) e[c] = _mm256_andnot_ps(none, e[c]);
      }
      const __m256 half_seg =
          first ? _mm256_setzero_ps() : _mm256_mul_ps(splat(0.5f), _mm256_sub_ps(at, t));
      for (int c = 0; c < 4; ++c) {
        const __m256 p = _mm256_load_ps(L_.prev[c]), sum = _mm256_load_ps(L_.sum[c]);
        _mm256_store_ps(
            L_.sum[c],
            _mm256_blendv_ps(sum, _mm256_fmadd_ps(half_seg, _mm256_add_ps(p, e[c]), sum), active));
        _mm256_store_ps(L_.prev[c], _mm256_blendv_ps(p, e[c], active));
      }
    }
    _mm256_store_ps(L_.t, _mm256_blendv_ps(t, at, moved));
    return static_cast<unsigned>(_mm256_movemask_ps(_mm256_and_ps(done, active)));
  }

  // AttenuationTable::lookup in lanes: per lane, entries i and i + 1 are one 32-byte load.
  void attenuation(__m256 s, __m256 e[4]) const {
    const AttenuationTable& a = v_.attenuation;
    const __m256 x = _mm256_min_ps(
        _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(s, splat(a.lo())), splat(a.inv_step())),
                      _mm256_setzero_ps()),
        splat(static_cast<float>(TfLut::kSize - 1)));
    const __m256i i = _mm256_min_epi32(_mm256_cvttps_epi32(x), splat(TfLut::kSize - 2));
    alignas(32) int32_t entry[kLanes];
    alignas(32) float frac[kLanes];
    _mm256_store_si256(reinterpret_cast<__m256i*>(entry), i);
    _mm256_store_ps(frac, _mm256_sub_ps(x, _mm256_cvtepi32_ps(i)));
    const float* table = reinterpret_cast<const float*>(a.data());
    __m128 v[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      const __m256 pair = _mm256_loadu_ps(table + 4 * static_cast<size_t>(entry[l]));
      const __m128 lo = _mm256_castps256_ps128(pair), hi = _mm256_extractf128_ps(pair, 1);
      v[l] = _mm_fmadd_ps(_mm_broadcast_ss(&frac[l]), _mm_sub_ps(hi, lo), lo);
    }
    const __m256 v0 = _mm256_set_m128(v[4], v[0]), v1 = _mm256_set_m128(v[5], v[1]);
    const __m256 v2 = _mm256_set_m128(v[6], v[2]), v3 = _mm256_set_m128(v[7], v[3]);
    const __m256 t0 = _mm256_unpacklo_ps(v0, v1), t1 = _mm256_unpackhi_ps(v0, v1);
    const __m256 t2 = _mm256_unpacklo_ps(v2, v3), t3 = _mm256_unpackhi_ps(v2, v3);
    e[0] = _mm256_shuffle_ps(t0, t2, 0x44), e[1] = _mm256_shuffle_ps(t0, t2, 0xee);
    e[2] = _mm256_shuffle_ps(t1, t3, 0x44), e[3] = _mm256_shuffle_ps(t1, t3, 0xee);
  }

  // The lanes of `live` that entered a brick they have not judged look at its value range; those
  // that may skip it move to its last grid point (walk_samples). Returns the lanes still walking.
  unsigned look(unsigned live) {
    if (!ranges_) return live;
    const __m256 t = _mm256_load_ps(L_.t);
    const __m256 need = _mm256_and_ps(
        lane_mask(live), _mm256_cmp_ps(t, _mm256_load_ps(L_.checked_until), _CMP_GE_OQ));
    // A look costs the same for one lane as for eight: put it off until half the lanes need one
    // or the first has waited kMaxLookDelay points (skipping is never required for the result).
    const unsigned waiting = static_cast<unsigned>(_mm256_movemask_ps(need));
    if (!waiting) return live;
    // After looks that skipped nothing (a MIP through tissue whose bricks all beat the running
    // maximum), wait longer, up to kMaxLookBackoff points: on the real CT with a ramp from air,
    // walking every point without looks was faster than looking at every brick.
    if ((look_limit_ > kMaxLookDelay ||
         2 * __builtin_popcount(waiting) < __builtin_popcount(live)) &&
        ++look_delay_ <= look_limit_)
      return live;
    look_delay_ = 0;
    const __m256 t1 = _mm256_load_ps(L_.t1);
    // Lanes in a brick the TF leaves empty walk to the first occupied one (`ahead`); the others
    // judge the brick they are in by its value range.
    __m256 ahead = _mm256_setzero_ps(), target = t1, ends = _mm256_setzero_ps();
    __m256 judge = need;
    if (bricks_) {
      __m256 leave = t1;
      unsigned none = 0;
      if (mode_ == Mode::max || mode_ == Mode::min) {
        // Bricks whose values cannot pass the running result are walked past too.
        const __m256 best = _mm256_load_ps(L_.best);
        const bool max = mode_ == Mode::max;
        none =
            bricks_->first_occupied(brick_rays_, waiting, t, t1, target, leave, [&](__m256i brick) {
              const __m256i at = _mm256_slli_epi32(brick, 1);
              return max ? _mm256_cmp_ps(gather_floats(ranges_, _mm256_add_epi32(at, splat(1))),
                                         best, _CMP_GT_OQ)
                         : _mm256_cmp_ps(gather_floats(ranges_, at), best, _CMP_LT_OQ);
            });
      } else {
        none = bricks_->first_occupied(brick_rays_, waiting, t, t1, target, leave);
      }
      ends = lane_mask(none);
      ahead = _mm256_andnot_ps(ends, _mm256_and_ps(need, _mm256_cmp_ps(target, t, _CMP_GT_OQ)));
      judge = _mm256_andnot_ps(_mm256_or_ps(ends, ahead), need);
      _mm256_store_ps(L_.checked_until,
                      _mm256_blendv_ps(_mm256_load_ps(L_.checked_until), target, ahead));
    }
    const __m256 o[3] = {_mm256_load_ps(L_.ox), _mm256_load_ps(L_.oy), _mm256_load_ps(L_.oz)};
    const __m256 d[3] = {_mm256_load_ps(L_.dx), _mm256_load_ps(L_.dy), _mm256_load_ps(L_.dz)};
    const __m256 zero = _mm256_setzero_ps();
    __m256 exit = splat(INFINITY);
    __m256i index = _mm256_setzero_si256();
    const int stride[3] = {1, brick_stride_y_, brick_stride_z_};
    for (int a = 0; a < 3; ++a) {
      // BrickGrid::brick_of: max(x, 0) sends a NaN to brick 0.
      const __m256 p = _mm256_fmadd_ps(t, d[a], o[a]);
      const __m256 size = splat(brick_size_[a]), inv_size = splat(inv_brick_size_[a]);
      const __m256 b = _mm256_min_ps(
          _mm256_max_ps(_mm256_floor_ps(_mm256_mul_ps(p, inv_size)), zero), splat(brick_last_[a]));
      index = _mm256_add_epi32(index, _mm256_mullo_epi32(_mm256_cvttps_epi32(b), splat(stride[a])));
      const __m256 low = _mm256_mul_ps(b, size);
      const __m256 high = _mm256_min_ps(_mm256_add_ps(low, size), splat(voxel_last_[a]));
      const __m256 face = _mm256_blendv_ps(low, high, _mm256_cmp_ps(d[a], zero, _CMP_GT_OQ));
      // A parallel axis gives NaN, which min_ps passes over (it returns its second operand).
      const __m256 at = _mm256_mul_ps(_mm256_sub_ps(face, o[a]), _mm256_load_ps(L_.inv_d[a]));
      exit = _mm256_min_ps(at, exit);
    }
    // X-ray: a lane judged here is in a brick the TF shows in (the occupancy walk passed the
    // others), whose attenuation counts: nothing to skip.
    __m256 skip = _mm256_setzero_ps();
    if (mode_ != Mode::integral) {
      const __m256i at = _mm256_slli_epi32(index, 1);
      const __m256 lo = gather_floats(ranges_, at);
      const __m256 hi = gather_floats(ranges_, _mm256_add_epi32(at, splat(1)));
      const __m256 best = _mm256_load_ps(L_.best);
      if (mode_ == Mode::max)
        skip = _mm256_cmp_ps(hi, best, _CMP_LE_OQ);
      else if (mode_ == Mode::min)
        skip = _mm256_cmp_ps(lo, best, _CMP_GE_OQ);
      else
        skip = _mm256_or_ps(_mm256_cmp_ps(lo, splat(iso_), _CMP_GE_OQ),
                            _mm256_cmp_ps(hi, splat(iso_), _CMP_LT_OQ));
    }
    _mm256_store_ps(L_.checked_until,
                    _mm256_blendv_ps(_mm256_load_ps(L_.checked_until), exit, judge));
    skip = _mm256_or_ps(_mm256_and_ps(skip, judge), ahead);
    if (!_mm256_movemask_ps(_mm256_or_ps(skip, ends))) {
      look_limit_ = std::min(2 * look_limit_, kMaxLookBackoff);
      return live;
    }
    look_limit_ = kMaxLookDelay;
    target = _mm256_blendv_ps(exit, target, ahead);
    const __m256 step = splat(step_), inv_step = splat(1.0f / step_);
    const __m256 last = _mm256_mul_ps(_mm256_floor_ps(_mm256_mul_ps(target, inv_step)), step);
    ends = _mm256_or_ps(ends, _mm256_and_ps(skip, _mm256_cmp_ps(last, t1, _CMP_GE_OQ)));
    const __m256 jump =
        _mm256_andnot_ps(ends, _mm256_and_ps(skip, _mm256_cmp_ps(last, t, _CMP_GT_OQ)));
    if (_mm256_movemask_ps(jump)) {
      _mm256_store_ps(L_.t, _mm256_blendv_ps(t, last, jump));
      // grid_cell(last) + 1, with the same fix-up for rounding.
      __m256 cell = _mm256_floor_ps(_mm256_mul_ps(last, inv_step));
      const __m256 one = splat(1.0f);
      cell = _mm256_add_ps(
          cell, _mm256_and_ps(one, _mm256_cmp_ps(_mm256_mul_ps(_mm256_add_ps(cell, one), step),
                                                 last, _CMP_LE_OQ)));
      _mm256_store_ps(L_.next_cell, _mm256_blendv_ps(_mm256_load_ps(L_.next_cell),
                                                     _mm256_add_ps(cell, one), jump));
      if (mode_ == Mode::iso) {
        const __m256 f = _mm256_sub_ps(sample_at(last), splat(iso_));
        _mm256_store_ps(L_.best, _mm256_blendv_ps(_mm256_load_ps(L_.best), f, jump));
      } else if (mode_ == Mode::integral) {
        for (int c = 0; c < 4; ++c)
          _mm256_store_ps(L_.prev[c], _mm256_blendv_ps(_mm256_load_ps(L_.prev[c]), zero, jump));
      }
    }
    return live & ~static_cast<unsigned>(_mm256_movemask_ps(ends));
  }

  // Writes the colours of rays first .. first + n - 1.
  void finish(size_t first, int n) {
    for (int l = 0; l < n; ++l) {
      const PacketRay& pr = rays_[first + static_cast<size_t>(l)];
      glm::vec4& out = out_[first + static_cast<size_t>(l)];
      out = glm::vec4(0.0f);
      if (!(pr.t1 > pr.t0)) continue;
      if (mode_ == Mode::iso) {
        if (L_.found[l])
          out = refine_iso_crossing(v_, pr.ray, L_.t[l], L_.cross_t[l], L_.best[l], L_.cross_f[l],
                                    bisections_, lights_)
                    .color;
        continue;
      }
      glm::vec4 tf(0.0f);
      if (mode_ == Mode::integral) {
        const float mu = L_.sum[3][l];
        if (!(mu > 0.0f)) continue;
        tf = glm::vec4(glm::vec3(L_.sum[0][l], L_.sum[1][l], L_.sum[2][l]) / mu, -std::expm1(-mu));
      } else {
        tf = v_.lut.lookup(L_.best[l]);
      }
      if (tf.a > 0.0f) out = glm::vec4(glm::vec3(tf) * tf.a, tf.a);
    }
  }

  const PreparedVolume& v_;
  LaneGrid<T> grid_;
  std::span<const PacketRay> rays_;
  std::span<glm::vec4> out_;
  std::span<const ShadingLight> lights_;
  float step_;
  int bisections_;
  float iso_;
  Mode mode_ = Mode::max;
  int look_delay_ = 0;                // points walked with a look put off
  int look_limit_ = kMaxLookDelay;    // how many, before the next look
  std::optional<LaneBricks> bricks_;  // the TF's empty bricks, where they may be walked past
  LaneBricks::Rays brick_rays_{};
  const float* ranges_ = nullptr;             // (min, max) per brick; null: no skipping
  float brick_size_[3] = {8.0f, 8.0f, 8.0f};  // cells per brick along each axis
  float inv_brick_size_[3] = {0.125f, 0.125f, 0.125f};
  float brick_last_[3] = {}, voxel_last_[3] = {};
  int brick_stride_y_ = 1, brick_stride_z_ = 1;
  ProjectionLanes L_{};
};

#endif  // IMX_PACKET_LANES

}  // namespace

bool packet_projection_supported(const PreparedVolume& v) {
#if IMX_PACKET_LANES
  const VolumeStyle s = v.object->style;
  if (s == VolumeStyle::dvr || (s == VolumeStyle::xray && v.object->xray_mode == XrayMode::average))
    return false;
  const glm::ivec3 d = v.grid.dims;
  if (d.x < 2 || d.y < 2 || d.z < 2) return false;
  const double voxels = static_cast<double>(d.x) * d.y * d.z;
  if (voxels + 4.0 >= 2147483647.0) return false;  // gathers take int32 voxel indices
  const BrickMinMax* r = skip_ranges(v);
  return !r || 8.0 * static_cast<double>(r->grid().count()) < 2147483647.0;
#else
  (void)v;
  return false;
#endif
}

void project_packets(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                     int bisections, std::span<const ShadingLight> lights,
                     std::span<glm::vec4> out) {
#if IMX_PACKET_LANES
  if (packet_projection_supported(v)) {
    run_lane_kernel<ProjectionKernel>(v, rays, step, bisections, lights, out);
    return;
  }
#endif
  project_each(v, rays, step, bisections, lights, out);
}

}  // namespace imx
