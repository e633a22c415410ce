// CSG interval classification of one sample ray (SPEC §8): the boundary events of the CSG
// primitives split the ray into intervals; the intervals some clipping state may accept become
// the ranges to march, and the CSG surfaces where the expression's value flips are kept.
// Pure: no allocation, no exceptions; the caller sizes the output spans.
#pragma once
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <type_traits>

#include "csg/csg_view.hpp"
#include "csg/mesh_windings.hpp"
#include "raster/fragment.hpp"
#include "slab/mix.hpp"

namespace imx {

// Boundary events closer than this (mm) are one group: coplanar faces toggle together, as in
// the reference (ReferenceParams::coincide).
inline constexpr float kCsgCoincide = 1e-3f;

// A part of the ray that some clipping state may accept, to be marched.
struct CsgRange {
  float t0 = 0.0f, t1 = 0.0f;
  PrimitiveMask geometric_inside = 0;  // region-presence primitives enclosing the whole range
  bool needs_test = false;             // visibility depends on which opacity-presence volumes show
};

// Where each CSG volume primitive's span lies on the ray (empty: t1 <= t0, as {}). No member
// initializers: the kernel keeps an uninitialized array of 64 per ray and fills what it reads.
struct CsgVolumeSpan {
  float t0, t1;
};

struct CsgIntervals {
  int surface_count = 0;      // into `surfaces`: the pass-through and drawn CSG surfaces, by depth
  int range_count = 0;        // into `ranges`, by depth, disjoint
  int intervals = 0;          // intervals between boundary groups (the seed's PSI, per ray)
  bool inconsistent = false;  // the fragments did not pair up (a lost or extra crossing)
};

// The capacity `ranges` needs for a row of `fragments` fragments.
inline size_t csg_range_capacity(size_t fragments) {
  return fragments + 2 * static_cast<size_t>(kMaxCsgPrimitives) + 1;
}

// Classifies one ray. `row`: its fragments by depth. `spans[k]`: CSG volume primitive k's span.
// `opacity_present(k, t)`: whether opacity-presence volume k shows at depth t (TF opacity above
// the threshold). `surfaces` needs row.size() entries, `ranges` csg_range_capacity(row.size()).
template <class OpacityPresent>
CsgIntervals classify_csg_ray(std::span<const Fragment> row, const CsgView& view,
                              std::span<const CsgVolumeSpan> spans,
                              const OpacityPresent& opacity_present, std::span<Fragment> surfaces,
                              std::span<CsgRange> ranges) {
  CsgIntervals out;
  CsgWindings windings(row, view.primitive_of_object);
  out.inconsistent = windings.inconsistent;

  // Volume span ends, sorted (at most 2 per primitive).
  struct VolumeEvent {
    float t;
    int k;
    bool enter;
  };
  VolumeEvent events[2 * kMaxCsgPrimitives];
  int n_events = 0;
  for (int k = 0; k < static_cast<int>(spans.size()); ++k)
    if (spans[k].t1 > spans[k].t0) {
      events[n_events++] = {spans[k].t0, k, true};
      events[n_events++] = {spans[k].t1, k, false};
    }
  std::sort(events, events + n_events,
            [](const VolumeEvent& a, const VolumeEvent& b) { return a.t < b.t; });

  PrimitiveMask volumes_inside = 0;
  auto inside = [&] { return windings.inside | volumes_inside; };
  // Some state holds whatever the opacity-presence primitives inside do.
  auto certain = [&](PrimitiveMask mask) {
    for (const ClipState& s : view.states)
      if ((s.ones & ~(mask & view.geometric)) == 0 && (s.zeros & mask) == 0) return true;
    return false;
  };
  auto present_at = [&](PrimitiveMask mask, float t) {
    PrimitiveMask p = mask & view.geometric;
    for (PrimitiveMask m = mask & ~view.geometric; m; m &= m - 1)
      if (int k = std::countr_zero(m); opacity_present(k, t)) p |= PrimitiveMask{1} << k;
    return p;
  };

  size_t fi = 0;
  int vi = 0;
  float t_prev = 0.0f;
  bool prev_accepted = false;
  bool after_group = false;  // intervals count from the first boundary group on
  // Ends the interval [t_prev, t_end]; an accepted one extends the last range when that ends
  // where it starts with the same geometric inside bits (ranges are cut at mesh surfaces and
  // region faces, not where an opacity-presence volume's span ends).
  auto close_interval = [&](float t_end) {
    if (!(t_end > t_prev)) return;  // a group's own width
    if (after_group) ++out.intervals;
    const bool contiguous = prev_accepted;
    const PrimitiveMask mask = inside();
    if (!(prev_accepted =
              mask != 0 && may_accept_any(view.states, mask, view.geometric, view.used)))
      return;
    const bool test = !certain(mask);
    const PrimitiveMask g = mask & view.geometric;
    CsgRange* last = out.range_count > 0 ? &ranges[out.range_count - 1] : nullptr;
    if (contiguous && last && last->geometric_inside == g) {
      last->t1 = t_end;
      last->needs_test |= test;
    } else {
      ranges[out.range_count++] = {t_prev, t_end, g, test};
    }
  };

  while (true) {
    // The next CSG event; non-CSG fragments before it pass through.
    while (fi < row.size() && CsgWindings::primitive_of(row[fi], view.primitive_of_object) < 0)
      surfaces[out.surface_count++] = row[fi++];
    const float tf = fi < row.size() ? row[fi].t : INFINITY;
    const float tv = vi < n_events ? events[vi].t : INFINITY;
    const float t = std::min(tf, tv);
    if (t == INFINITY) break;
    close_interval(t);

    // The group: every CSG event within kCsgCoincide of t, applied together.
    const PrimitiveMask before = inside();
    float group_end = t;
    glm::vec3 colour_sum(0.0f);
    float alpha_sum = 0.0f, transmittance = 1.0f;
    int group_fragments = 0, first = -1;
    const int group_start = out.surface_count;
    while (true) {
      // Written as !(a > b) so that a NaN depth is consumed too and the loop always advances.
      const bool f_next = fi < row.size() && !(row[fi].t > t + kCsgCoincide);
      const bool v_next = vi < n_events && !(events[vi].t > t + kCsgCoincide);
      if (!f_next && !v_next) break;
      if (f_next && (!v_next || row[fi].t <= events[vi].t)) {
        const Fragment& f = row[fi++];
        group_end = std::max(group_end, f.t);
        if (!windings.pass(f, view.primitive_of_object)) {
          surfaces[out.surface_count++] = f;  // a non-CSG surface within the group
          continue;
        }
        if (first < 0) first = static_cast<int>(fi - 1);
        colour_sum += glm::vec3(f.color);
        alpha_sum += f.color.a;
        transmittance *= 1.0f - f.color.a;
        ++group_fragments;
      } else {
        const VolumeEvent& e = events[vi++];
        group_end = std::max(group_end, e.t);
        const PrimitiveMask bit = PrimitiveMask{1} << e.k;
        volumes_inside = e.enter ? volumes_inside | bit : volumes_inside & ~bit;
      }
    }
    out.inconsistent |= windings.inconsistent;
    if (group_fragments > 0 &&
        view.value(present_at(before, t)) != view.value(present_at(inside(), t))) {
      // In front of the group's pass-through surfaces, which lie at t or behind it.
      for (int i = out.surface_count; i > group_start; --i) surfaces[i] = surfaces[i - 1];
      ++out.surface_count;
      surfaces[group_start] = row[first];
      surfaces[group_start].t = t;
      surfaces[group_start].color = m1_visibility(colour_sum, alpha_sum, 1.0f - transmittance);
    }
    t_prev = group_end;
    after_group = true;
  }
  // Whatever still encloses the ray's end lost a crossing; it is not marched to infinity.
  if (windings.inside != 0) out.inconsistent = true;
  return out;
}

}  // namespace imx
