#include "volume/packet_projection.hpp"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "volume/packet_projection.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <type_traits>

#include "volume/iso_crossing.hpp"
#include "volume/lane_bricks-inl.hpp"
#include "volume/lane_grid-inl.hpp"
#include "volume/lane_kernel-inl.hpp"
#include "volume/projection.hpp"

HWY_BEFORE_NAMESPACE();
namespace imx::HWY_NAMESPACE {
namespace {

using namespace lanes;

enum class Mode : uint8_t { max, min, integral, iso };

constexpr int kMaxLookDelay = 4;     // points a lane that entered a new brick may walk unjudged
constexpr int kMaxLookBackoff = 64;  // the most points between looks after fruitless ones

// The per-lane state, structure of arrays so that a step loads whole vectors.
struct ProjectionLanes {
  HWY_ALIGN float ox[kLanes], oy[kLanes], oz[kLanes];  // the ray in index space, same parameter t
  HWY_ALIGN float dx[kLanes], dy[kLanes], dz[kLanes];
  HWY_ALIGN float inv_d[3][kLanes];       // 1 / d per axis, NaN where the ray runs parallel
  HWY_ALIGN float t[kLanes];              // the last point sampled
  HWY_ALIGN float t1[kLanes];             // where the span ends
  HWY_ALIGN float next_cell[kLanes];      // the next point is next_cell * step (or t1)
  HWY_ALIGN float checked_until[kLanes];  // the brick verdict of the last look holds up to here
  HWY_ALIGN float best[kLanes];           // max / min: the running value; iso: value - iso at t
  HWY_ALIGN float best_t[kLanes];         // max / min: where it was first seen
  HWY_ALIGN float cross_t[kLanes];        // iso: the point after the sign change
  HWY_ALIGN float cross_f[kLanes];        //   and value - iso there
  HWY_ALIGN int32_t found[kLanes];        // iso: a sign change was seen
  HWY_ALIGN float sum[4][kLanes];         // integral: (mu r, mu g, mu b, mu) integrated
  HWY_ALIGN float prev[4][kLanes];        //   and at t
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
      bricks_->rays(origin, dir, brick_rays_);
    }
    const VF t = load(L_.t);
    live &= ~update(live, sample_at(t), t, true);
    look_delay_ = kMaxLookDelay;  // every lane looks at its first brick at once
    look_limit_ = kMaxLookDelay;
    return look(live);
  }

  // The next point in every live lane; returns the lanes still walking.
  unsigned advance(unsigned live) {
    const MF active = lane_mask(live);
    const VF t1 = load(L_.t1), next_cell = load(L_.next_cell);
    const VF b = hn::Min(t1, hn::Mul(next_cell, splat(step_)));
    unsigned done = update(live, sample_at(b), b, false);
    store(hn::IfThenElse(active, hn::Add(next_cell, splat(1.0f)), next_cell), L_.next_cell);
    done |= bits_of(hn::And(active, hn::Ge(b, t1)));
    return look(live & ~done);
  }

  VF sample_at(VF t) const {
    return grid_.sample(hn::MulAdd(t, load(L_.dx), load(L_.ox)),
                        hn::MulAdd(t, load(L_.dy), load(L_.oy)),
                        hn::MulAdd(t, load(L_.dz), load(L_.oz)));
  }

  // Takes the value s at point `at` in the lanes of `live`; returns those that are done (the TF
  // saturated, or a sign change found).
  unsigned update(unsigned live, VF s, VF at, bool first) {
    const MF active = lane_mask(live);
    const VF t = load(L_.t);
    MF done = hn::Not(all_lanes());
    MF moved = active;  // lanes whose last point becomes `at`
    if (mode_ == Mode::max || mode_ == Mode::min) {
      const VF best = load(L_.best);
      const bool max = mode_ == Mode::max;
      MF better = hn::And(active, max ? hn::Gt(s, best) : hn::Lt(s, best));
      if constexpr (NoData) better = hn::AndNot(no_data_lanes(s), better);  // never the max or min
      const VF nbest = hn::IfThenElse(better, s, best);
      store(nbest, L_.best);
      store(hn::IfThenElse(better, at, load(L_.best_t)), L_.best_t);
      done = max ? hn::Ge(nbest, splat(v_.limits.constant_from))
                 : hn::Le(nbest, splat(v_.limits.constant_up_to));
    } else if (mode_ == Mode::iso) {
      const VF f = hn::Sub(s, splat(iso_));
      const VF fa = load(L_.best);
      if (!first) {
        const VF zero = hn::Zero(DF());
        done = hn::Xor(hn::Lt(fa, zero), hn::Lt(f, zero));
        done = hn::And(done, active);
        // A crossing lies between two samples of data (find_iso_crossing).
        if constexpr (NoData) done = hn::AndNot(hn::Or(no_data_lanes(f), no_data_lanes(fa)), done);
        store(hn::IfThenElse(done, at, load(L_.cross_t)), L_.cross_t);
        store(hn::IfThenElse(done, f, load(L_.cross_f)), L_.cross_f);
        store(hn::Or(load(L_.found), hn::VecFromMask(DI(), to_int(done))), L_.found);
        moved = hn::AndNot(done, active);  // the bracket starts at t: keep it
      }
      store(hn::IfThenElse(moved, f, fa), L_.best);
    } else {
      VF e[4];
      attenuation(s, e);
      if constexpr (NoData) {  // no attenuation, as a value of opacity 0
        const MF none = no_data_lanes(s);
        for (int c = 0; c < 4; ++c) e[c] = hn::IfThenZeroElse(none, e[c]);
      }
      const VF half_seg = first ? hn::Zero(DF()) : hn::Mul(splat(0.5f), hn::Sub(at, t));
      for (int c = 0; c < 4; ++c) {
        const VF p = load(L_.prev[c]), sum = load(L_.sum[c]);
        store(hn::IfThenElse(active, hn::MulAdd(half_seg, hn::Add(p, e[c]), sum), sum), L_.sum[c]);
        store(hn::IfThenElse(active, e[c], p), L_.prev[c]);
      }
    }
    store(hn::IfThenElse(moved, at, t), L_.t);
    return bits_of(hn::And(done, active));
  }

  // AttenuationTable::lookup in lanes: entries i and i + 1 interpolated, a gather per channel.
  void attenuation(VF s, VF e[4]) const {
    const AttenuationTable& a = v_.attenuation;
    const VF x =
        hn::Min(hn::Max(hn::Mul(hn::Sub(s, splat(a.lo())), splat(a.inv_step())), hn::Zero(DF())),
                splat(static_cast<float>(TfLut::kSize - 1)));
    const VI i = hn::Min(hn::ConvertTo(DI(), x), splat(TfLut::kSize - 2));
    const VF f = hn::Sub(x, hn::ConvertTo(DF(), i));
    const float* table = reinterpret_cast<const float*>(a.data());
#if !IMX_LANE_QUADS
    const VI entry = hn::ShiftLeft<2>(i);  // four channels an entry
    for (int c = 0; c < 4; ++c)
      e[c] = lerp(gather_floats(table, hn::Add(entry, splat(c))),
                  gather_floats(table, hn::Add(entry, splat(4 + c))), f);
#else
    // A lane's two entries are eight adjacent floats: loaded whole, lerped, then transposed
    // into channels, where eight gathers (one per channel and entry) each loaded every lane.
    // X-ray of the fractional float32 CT: 322 -> 276 ms (AVX3), 423 -> 408 (AVX2); the real CT
    // at SSE4 (no gathers) 253 -> 179; int16 CTs unchanged.
    HWY_ALIGN int32_t at[kLanes];
    HWY_ALIGN float frac[kLanes];
    store(i, at), store(f, frac);
    V4 q[kLanes];
    for (int l = 0; l < kLanes; ++l) q[l] = lerp_entries(table + 4 * at[l], frac[l]);
    transpose_quads(q, e[0], e[1], e[2], e[3]);
#endif
  }

  // The lanes of `live` that entered a brick they have not judged look at its value range; those
  // that may skip it move to its last grid point (walk_samples). Returns the lanes still walking.
  unsigned look(unsigned live) {
    if (!ranges_) return live;
    const VF t = load(L_.t);
    const MF need = hn::And(lane_mask(live), hn::Ge(t, load(L_.checked_until)));
    // A look costs the same for one lane as for all: put it off until half the lanes need one
    // or the first has waited kMaxLookDelay points (skipping is never required for the result).
    const unsigned waiting = bits_of(need);
    if (!waiting) return live;
    // After looks that skipped nothing (a MIP through tissue whose bricks all beat the running
    // maximum), wait longer, up to kMaxLookBackoff points: on the real CT with a ramp from air,
    // walking every point without looks was faster than looking at every brick.
    if ((look_limit_ > kMaxLookDelay ||
         2 * __builtin_popcount(waiting) < __builtin_popcount(live)) &&
        ++look_delay_ <= look_limit_)
      return live;
    look_delay_ = 0;
    const VF t1 = load(L_.t1);
    const MF none_set = hn::Not(all_lanes());
    // Lanes in a brick the TF leaves empty walk to the first occupied one (`ahead`); the others
    // judge the brick they are in by its value range.
    MF ahead = none_set, ends = none_set;
    VF target = t1;
    MF judge = need;
    if (bricks_) {
      VF leave = t1;
      unsigned none = 0;
      if (mode_ == Mode::max || mode_ == Mode::min) {
        // Bricks whose values cannot pass the running result are walked past too.
        const VF best = load(L_.best);
        const bool max = mode_ == Mode::max;
        none = bricks_->first_occupied(
            brick_rays_, waiting, t, t1, target, leave, [&](VI brick) HWY_ATTR {
              const VI at = hn::ShiftLeft<1>(brick);
              return max ? hn::Gt(gather_floats(ranges_, hn::Add(at, splat(1))), best)
                         : hn::Lt(gather_floats(ranges_, at), best);
            });
      } else {
        none = bricks_->first_occupied(brick_rays_, waiting, t, t1, target, leave);
      }
      ends = lane_mask(none);
      ahead = hn::AndNot(ends, hn::And(need, hn::Gt(target, t)));
      judge = hn::AndNot(hn::Or(ends, ahead), need);
      store(hn::IfThenElse(ahead, target, load(L_.checked_until)), L_.checked_until);
    }
    const VF o[3] = {load(L_.ox), load(L_.oy), load(L_.oz)};
    const VF d[3] = {load(L_.dx), load(L_.dy), load(L_.dz)};
    const VF zero = hn::Zero(DF());
    VF exit = splat(INFINITY);
    VI index = hn::Zero(DI());
    const int stride[3] = {1, brick_stride_y_, brick_stride_z_};
    for (int a = 0; a < 3; ++a) {
      // BrickGrid::brick_of: max(x, 0) sends a NaN to brick 0.
      const VF p = hn::MulAdd(t, d[a], o[a]);
      const VF size = splat(brick_size_[a]), inv_size = splat(inv_brick_size_[a]);
      const VF b = hn::Min(hn::Max(hn::Floor(hn::Mul(p, inv_size)), zero), splat(brick_last_[a]));
      index = hn::Add(index, hn::Mul(hn::ConvertTo(DI(), b), splat(stride[a])));
      const VF low = hn::Mul(b, size);
      const VF high = hn::Min(hn::Add(low, size), splat(voxel_last_[a]));
      const VF face = hn::IfThenElse(hn::Gt(d[a], zero), high, low);
      // A parallel axis gives NaN, which Min passes over (it returns its second operand).
      const VF at = hn::Mul(hn::Sub(face, o[a]), load(L_.inv_d[a]));
      exit = hn::Min(at, exit);
    }
    // X-ray: a lane judged here is in a brick the TF shows in (the occupancy walk passed the
    // others), whose attenuation counts: nothing to skip.
    MF skip = none_set;
    if (mode_ != Mode::integral) {
      const VI at = hn::ShiftLeft<1>(index);
      const VF lo = gather_floats(ranges_, at);
      const VF hi = gather_floats(ranges_, hn::Add(at, splat(1)));
      const VF best = load(L_.best);
      if (mode_ == Mode::max)
        skip = hn::Le(hi, best);
      else if (mode_ == Mode::min)
        skip = hn::Ge(lo, best);
      else
        skip = hn::Or(hn::Ge(lo, splat(iso_)), hn::Lt(hi, splat(iso_)));
    }
    store(hn::IfThenElse(judge, exit, load(L_.checked_until)), L_.checked_until);
    skip = hn::Or(hn::And(skip, judge), ahead);
    if (hn::AllFalse(DF(), hn::Or(skip, ends))) {
      look_limit_ = std::min(2 * look_limit_, kMaxLookBackoff);
      return live;
    }
    look_limit_ = kMaxLookDelay;
    target = hn::IfThenElse(ahead, target, exit);
    const VF step = splat(step_), inv_step = splat(1.0f / step_);
    const VF last = hn::Mul(hn::Floor(hn::Mul(target, inv_step)), step);
    ends = hn::Or(ends, hn::And(skip, hn::Ge(last, t1)));
    const MF jump = hn::AndNot(ends, hn::And(skip, hn::Gt(last, t)));
    if (!hn::AllFalse(DF(), jump)) {
      store(hn::IfThenElse(jump, last, t), L_.t);
      // grid_cell(last) + 1, with the same fix-up for rounding.
      VF cell = hn::Floor(hn::Mul(last, inv_step));
      const VF one = splat(1.0f);
      cell =
          hn::Add(cell, hn::IfThenElseZero(hn::Le(hn::Mul(hn::Add(cell, one), step), last), one));
      store(hn::IfThenElse(jump, hn::Add(cell, one), load(L_.next_cell)), L_.next_cell);
      if (mode_ == Mode::iso) {
        const VF f = hn::Sub(sample_at(last), splat(iso_));
        store(hn::IfThenElse(jump, f, load(L_.best)), L_.best);
      } else if (mode_ == Mode::integral) {
        for (int c = 0; c < 4; ++c) store(hn::IfThenZeroElse(jump, load(L_.prev[c])), L_.prev[c]);
      }
    }
    return live & ~bits_of(ends);
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
  LaneBricks::Rays brick_rays_;
  const float* ranges_ = nullptr;             // (min, max) per brick; null: no skipping
  float brick_size_[3] = {8.0f, 8.0f, 8.0f};  // cells per brick along each axis
  float inv_brick_size_[3] = {0.125f, 0.125f, 0.125f};
  float brick_last_[3] = {}, voxel_last_[3] = {};
  int brick_stride_y_ = 1, brick_stride_z_ = 1;
  ProjectionLanes L_{};
};

}  // namespace

void project_lanes(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                   int bisections, std::span<const ShadingLight> lights, std::span<glm::vec4> out) {
  run_lane_kernel<ProjectionKernel>(v, rays, step, bisections, lights, out);
}

}  // namespace imx::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "volume/simd_targets.hpp"

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

HWY_EXPORT(project_lanes);

}  // namespace

bool packet_projection_supported(const PreparedVolume& v) {
  const VolumeStyle s = v.object->style;
  if (s == VolumeStyle::dvr || (s == VolumeStyle::xray && v.object->xray_mode == XrayMode::average))
    return false;
  const glm::ivec3 d = v.grid.dims;
  if (d.x < 2 || d.y < 2 || d.z < 2) return false;
  const double voxels = static_cast<double>(d.x) * d.y * d.z;
  if (voxels + 4.0 >= 2147483647.0) return false;  // gathers take int32 voxel indices
  const BrickMinMax* r = skip_ranges(v);
  return !r || 8.0 * static_cast<double>(r->grid().count()) < 2147483647.0;
}

void project_packets(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                     int bisections, std::span<const ShadingLight> lights,
                     std::span<glm::vec4> out) {
  if (packet_projection_supported(v)) {
    apply_simd_environment();
    HWY_DYNAMIC_DISPATCH(project_lanes)(v, rays, step, bisections, lights, out);
    return;
  }
  project_each(v, rays, step, bisections, lights, out);
}

}  // namespace imx
#endif  // HWY_ONCE
