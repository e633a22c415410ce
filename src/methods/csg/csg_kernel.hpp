// The csg kernel (SPEC §8, seed 004): CSG of volumes and closed meshes evaluated per ray. The
// boundary events of the primitives give the intervals (classify_csg_ray); only accepted ranges
// of the CSG volumes are marched, on mdvr's common grid; per step, the clipping states decide
// whether the step shows, from which primitives are present. Pure: no allocation.
#pragma once
#include <cmath>
#include <new>
#include <span>
#include <type_traits>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "csg/csg_view.hpp"
#include "csg/ray_intervals.hpp"
#include "frame/mixing_plan.hpp"
#include "methods/mdvr/mdvr_kernel.hpp"
#include "raster/fragment.hpp"
#include "slab/mix.hpp"
#include "slab/over.hpp"
#include "volume/classify.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/ray_volumes.hpp"
#include "volume/volume_marcher.hpp"

namespace imx {

// Scratch the caller sizes for a row of n fragments: n surfaces, csg_range_capacity(n) ranges.
struct CsgScratch {
  std::span<Fragment> surfaces;
  std::span<CsgRange> ranges;
};

// The most interior media one ray marches.
inline constexpr int kMaxRayMedia = 16;

// One source of steps: a volume over its span (not in the expression), a CSG volume over the
// accepted ranges within its span, or a mesh's interior medium over the ranges it encloses.
class CsgSource {
 public:
  // A volume: `bit` 0 when it is not a CSG primitive (then `ranges` holds just its span).
  CsgSource(std::span<const PreparedVolume> volumes, int v, PrimitiveMask bit, RayInterval span,
            std::span<const CsgRange> ranges, const Ray& ray, float step,
            std::span<const ShadingLight> lights)
      : volume_(&volumes[v]),
        volume_index_(v),
        ray_(&ray),
        lights_(lights),
        ranges_(ranges),
        bit_(bit),
        step_(step),
        lo_(span.t0),
        hi_(span.t1) {}
  // An interior medium of mesh primitive `bit`.
  CsgSource(const CsgMedium& m, PrimitiveMask bit, std::span<const CsgRange> ranges, float step)
      : medium_(m), ranges_(ranges), bit_(bit), step_(step) {}

  // The next slab and the range it lies in (-1 for a volume outside the expression).
  bool next(Slab& out, int& range) {
    return volume_ ? next_volume(out, range) : next_medium(out, range);
  }
  PrimitiveMask bit() const { return bit_; }
  // Its priority for exclusive mixing.
  uint8_t rank(const MixingView& mixing) const {
    return volume_ ? mixing.rank[volume_index_] : mixing.medium_rank;
  }
  float unit_distance() const {
    return volume_ ? volume_->lut.unit_distance() : medium_.unit_distance;
  }
  // The opacity a slab of length `len` exceeds where its primitive counts as present.
  float threshold(float presence_threshold, float len) const {
    if (presence_threshold <= 0.0f) return 0.0f;
    return correct_opacity(presence_threshold, len, unit_distance());
  }

 private:
  bool next_volume(Slab& out, int& range) {
    while (true) {
      if (live_ && marcher_.next(out)) {
        range = bit_ ? r_ : -1;
        return true;
      }
      if (!bit_ && r_ >= 0) return false;  // the whole span is done
      float t0 = lo_, t1 = hi_;
      if (bit_) {
        while (++r_ < static_cast<int>(ranges_.size()) && ranges_[r_].t1 <= lo_) {
        }
        if (r_ >= static_cast<int>(ranges_.size()) || ranges_[r_].t0 >= hi_) return false;
        t0 = std::max(t0, ranges_[r_].t0);
        t1 = std::min(t1, ranges_[r_].t1);
      } else {
        r_ = 0;
      }
      // In place: assigning a built marcher copies it (as mdvr's kernel notes).
      new (&marcher_) VolumeMarcher(*volume_, *ray_, t0, t1, step_, lights_, SlabExtent::grid);
      live_ = true;
    }
  }

  bool next_medium(Slab& out, int& range) {
    while (!(t_ < t_end_)) {
      while (++r_ < static_cast<int>(ranges_.size()) && !(ranges_[r_].geometric_inside & bit_)) {
      }
      if (r_ >= static_cast<int>(ranges_.size())) return false;
      t_ = ranges_[r_].t0;
      t_end_ = ranges_[r_].t1;
    }
    const double back = std::min<double>(t_end_, (grid_cell(t_, step_) + 1.0) * step_);
    const float a =
        correct_opacity(medium_.opacity, static_cast<float>(back - t_), medium_.unit_distance);
    out = Slab::between(static_cast<float>(t_), static_cast<float>(back),
                        glm::vec4(medium_.color * a, a));
    t_ = back;
    range = r_;
    return true;
  }

  const PreparedVolume* volume_ = nullptr;
  int volume_index_ = -1;
  const Ray* ray_ = nullptr;
  std::span<const ShadingLight> lights_;
  CsgMedium medium_;
  std::span<const CsgRange> ranges_;
  PrimitiveMask bit_ = 0;
  float step_ = 1.0f;
  float lo_ = 0.0f, hi_ = 0.0f;  // a volume's span
  int r_ = -1;                   // the range being marched
  VolumeMarcher marcher_;
  bool live_ = false;
  double t_ = 0.0, t_end_ = 0.0;  // a medium's position in its range
};

// Classifies one sample ray (trace_csg and `intermix-lab csg --intervals`): the CSG volumes' spans from
// `rv` (not its `marched` flags: a transparent volume still has a region), presence of opacity
// volumes by one TF lookup at depth t, then classify_csg_ray. `surfaces` needs row.size() entries,
// `ranges` csg_range_capacity(row.size()).
inline CsgIntervals classify_csg_sample(const Ray& ray, std::span<const Fragment> row,
                                        std::span<const PreparedVolume> volumes,
                                        const RayVolumes& rv, const CsgView& csg,
                                        std::span<Fragment> surfaces, std::span<CsgRange> ranges) {
  CsgVolumeSpan spans[kMaxCsgPrimitives];  // only the first primitive_count are read
  for (int k = 0; k < csg.primitive_count; ++k) spans[k] = CsgVolumeSpan{};
  for (int v = 0; v < rv.count; ++v)
    if (int k = csg.primitive_of_volume[v]; k >= 0) spans[k] = {rv.span[v].t0, rv.span[v].t1};
  auto opacity_present = [&](int k, float t) {
    const PreparedVolume& v = volumes[csg.volume_of_primitive[k]];
    // No data is not present (opacity 0); a label volume's winning label decides.
    return volume_look(v, v.to_index(ray.at(t))).a > csg.presence_threshold;
  };
  return classify_csg_ray(row, csg, std::span<const CsgVolumeSpan>(spans, csg.primitive_count),
                          opacity_present, surfaces, ranges);
}

// Premultiplied RGBA seen along `ray` through a CSG scene: mdvr's steps and binary surfaces,
// with the expression deciding which CSG steps and surfaces show. Without CSG primitives on the
// ray and with a union of every volume it is trace_mdvr's image, bit for bit.
inline glm::vec4 trace_csg(const Ray& ray, std::span<const Fragment> row,
                           std::span<const PreparedVolume> volumes,
                           std::span<const ShadingLight> lights, const MdvrParams& p,
                           const CsgView& csg, const MixingView& mixing, CsgScratch scratch,
                           VolumeMask may_show = kEveryVolume, CsgIntervals* stats = nullptr) {
  const RayVolumes rv(ray, volumes, p.step, p.iso_bisections, lights, may_show);
  const CsgIntervals iv =
      classify_csg_sample(ray, row, volumes, rv, csg, scratch.surfaces, scratch.ranges);
  if (stats) *stats = iv;
  const std::span<const Fragment> surfaces(scratch.surfaces.data(), iv.surface_count);
  const std::span<const CsgRange> ranges(scratch.ranges.data(), iv.range_count);

  glm::vec4 acc(0.0f);
  SurfacesInDepthOrder in_order{surfaces, rv};
  auto composite_surfaces_until = [&](double t) { in_order.composite_until(t, acc, p.ert); };

  // The sources, built in place only for what this ray meets (as in mdvr).
  static_assert(std::is_trivially_destructible_v<CsgSource>);
  constexpr int kMaxSources = kMaxRayVolumes + kMaxRayMedia;
  alignas(CsgSource) unsigned char storage[kMaxSources * sizeof(CsgSource)];
  CsgSource* sources = reinterpret_cast<CsgSource*>(storage);
  int n = 0;
  for (int v = 0; v < rv.count; ++v) {
    if (!rv.marched[v]) continue;
    const int k = csg.primitive_of_volume[v];
    if (k < 0) {
      const CsgRange whole{rv.span[v].t0, rv.span[v].t1, 0, false};
      new (&sources[n++])
          CsgSource(volumes, v, 0, rv.span[v], std::span(&whole, 1), ray, p.step, lights);
    } else if (!ranges.empty()) {
      new (&sources[n++])
          CsgSource(volumes, v, PrimitiveMask{1} << k, rv.span[v], ranges, ray, p.step, lights);
    }
  }
  int media = 0;
  PrimitiveMask enclosing = 0;
  for (const CsgRange& r : ranges) enclosing |= r.geometric_inside;
  for (PrimitiveMask m = enclosing & csg.with_medium; m && media < kMaxRayMedia; m &= m - 1) {
    const int k = std::countr_zero(m);
    new (&sources[n++]) CsgSource(csg.medium[k], PrimitiveMask{1} << k, ranges, p.step);
    ++media;
  }

  // Whether a step of the sources in `range` shows, given the CSG primitives `present` in it.
  auto shows = [&](int range, PrimitiveMask present) {
    const CsgRange& r = ranges[range];
    present |= r.geometric_inside;
    return !r.needs_test || csg.value(present);
  };

  if (n == 1) {
    // One source: its slabs are the grid steps, nothing to mix (mdvr's single-volume path).
    CsgSource& s = sources[0];
    Slab slab;
    int range;
    while (acc.a < p.ert && s.next(slab, range)) {
      composite_surfaces_until(slab.front());
      if (acc.a >= p.ert) break;
      if (range < 0) {
        acc = over(acc, slab.color);
      } else if (slab.color.a > s.threshold(csg.presence_threshold, slab.thickness) &&
                 shows(range, s.bit())) {
        acc = over(acc, slab.color);
      }
    }
  } else if (n > 1) {
    Slab heads[kMaxSources];
    int head_range[kMaxSources];
    bool live[kMaxSources] = {};
    for (int m = 0; m < n; ++m) live[m] = sources[m].next(heads[m], head_range[m]);
    glm::vec4 step_colors[kMaxSources];
    uint8_t step_ranks[kMaxSources];
    float step_thresholds[kMaxSources];
    while (acc.a < p.ert) {
      const float back = nearest_back(heads, live, n);
      if (back == INFINITY) break;
      const float same_step = back - 1e-3f * p.step;
      float front = back;
      // The step's colours in source order (as mdvr mixes them); CSG ones are kept only if
      // their primitive is present and the step shows.
      int k = 0, range = -1;
      PrimitiveMask present = 0;
      bool from_csg[kMaxSources];
      // A head thinner than the tolerance (a range can be that short) is taken when it ends
      // the step, so that every round consumes one.
      for (int m = 0; m < n; ++m)
        if (live[m] && (heads[m].front() < same_step || heads[m].t_back <= back)) {
          front = std::min(front, heads[m].front());
          from_csg[k] = head_range[m] >= 0;
          const bool csg_present =
              from_csg[k] &&
              heads[m].color.a > sources[m].threshold(csg.presence_threshold, heads[m].thickness);
          if (csg_present) {
            range = head_range[m];
            present |= sources[m].bit();
          }
          if (!from_csg[k] || csg_present) {
            if (mixing.exclusive) {
              step_ranks[k] = sources[m].rank(mixing);
              step_thresholds[k] =
                  correct_opacity(mixing.threshold, heads[m].thickness, sources[m].unit_distance());
            }
            step_colors[k++] = heads[m].color;
          }
          live[m] = sources[m].next(heads[m], head_range[m]);
        }
      if (range >= 0 && !shows(range, present)) {
        int kept = 0;
        for (int c = 0; c < k; ++c)
          if (!from_csg[c]) {
            step_colors[kept] = step_colors[c];
            step_ranks[kept] = step_ranks[c];
            step_thresholds[kept++] = step_thresholds[c];
          }
        k = kept;
      }
      composite_surfaces_until(front);
      if (acc.a >= p.ert) break;
      const std::span<const glm::vec4> colors(step_colors, k);
      acc = over(acc, mixing.exclusive
                          ? mix_exclusive(colors, std::span<const uint8_t>(step_ranks, k),
                                          std::span<const float>(step_thresholds, k))
                          : mix_m1(colors));
    }
  }
  composite_surfaces_until(INFINITY);
  return acc;
}

}  // namespace imx
