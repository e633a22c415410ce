// The reference kernel (SPEC §3): one sample ray through every volume and surface, exactly.
// Written independently of the slab algebra so it can judge it. Pure: no allocation.
#pragma once
#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>
#include <span>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "csg/mesh_windings.hpp"
#include "frame/csg_frame.hpp"
#include "frame/mixing_plan.hpp"
#include "raster/fragment.hpp"
#include "volume/classify.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/ray_volumes.hpp"

namespace imx {

struct ReferenceParams {
  MixingView mixing;        // how co-located volume samples mix (SPEC §5)
  double step = 0.1;        // common sampling step, mm
  float ert = 0.999f;       // stop once the accumulated opacity reaches this
  double coincide = 1e-3;   // surfaces closer than this (mm) are co-located and mixed
  int iso_bisections = 10;  // refinement steps of an iso-surface crossing
};

namespace detail {

// Front-to-back `over` of premultiplied (C, A) under the accumulated colour.
inline void composite(glm::vec4& acc, const glm::vec4& c) {
  float t = 1.0f - acc.a;
  acc += t * c;
}

// Accumulation-level mixing of co-located contributions (SPEC §5, M1).
struct M1Mix {
  glm::vec3 colour_sum{0.0f};
  float alpha_sum = 0.0f;
  float transmittance = 1.0f;
  void add(const glm::vec4& c) {
    colour_sum += glm::vec3(c);
    alpha_sum += c.a;
    transmittance *= 1.0f - c.a;
  }
  void merge(const M1Mix& other) {
    colour_sum += other.colour_sum;
    alpha_sum += other.alpha_sum;
    transmittance *= other.transmittance;
  }
  glm::vec4 result() const {
    float a = 1.0f - transmittance;
    if (alpha_sum <= 0.0f) return glm::vec4(0.0f);
    return glm::vec4(colour_sum / alpha_sum * a, a);
  }
};

// Exclusive mixing (SPEC §5), written apart from the slab algebra's: the best-ranked group with
// a member above its threshold wins alone, else the worst-ranked group with any opacity.
struct ExclusiveMix {
  static constexpr int kMax = kMaxRayVolumes + kMaxCsgPrimitives;
  glm::vec4 colour[kMax];
  uint8_t rank[kMax];
  float threshold[kMax];
  int n = 0;
  void add(const glm::vec4& c, uint8_t r, float t) {
    if (n == kMax) return;
    colour[n] = c;
    rank[n] = r;
    threshold[n++] = t;
  }
  glm::vec4 result() const {
    int best = 256, worst = -1;
    for (int i = 0; i < n; ++i) {
      if (colour[i].a > threshold[i]) best = std::min<int>(best, rank[i]);
      if (colour[i].a > 0.0f) worst = std::max<int>(worst, rank[i]);
    }
    M1Mix winners;
    for (int i = 0; i < n; ++i)
      if (rank[i] == (best < 256 ? best : worst)) winners.add(colour[i]);
    return winners.result();
  }
};

}  // namespace detail

// Where the CSG primitives are present along a ray, for the reference: meshes by winding,
// volumes by their spans and, with opacity presence, their TF opacity at the point (SPEC §8).
struct ReferenceCsg {
  const CsgView& view;
  const RayVolumes& rv;
  std::span<const PreparedVolume> volumes;
  const Ray& ray;
  CsgWindings windings;

  ReferenceCsg(const CsgView& v, const RayVolumes& r, std::span<const PreparedVolume> vols,
               const Ray& ray_, std::span<const Fragment> surfaces)
      : view(v), rv(r), volumes(vols), ray(ray_), windings(surfaces, v.primitive_of_object) {}

  // The primitives present at depth `t`; `region_t` decides span membership (a point just
  // before or after a surface group), `t` the TF opacity.
  PrimitiveMask present(double region_t, double t) const {
    PrimitiveMask p = windings.inside;
    for (int k = 0; k < view.primitive_count; ++k) {
      const int v = view.volume_of_primitive[k];
      if (v < 0 || v >= rv.count) continue;
      const RayInterval& s = rv.span[v];
      if (!(s.t0 <= region_t && region_t < s.t1)) continue;
      const PrimitiveMask bit = PrimitiveMask{1} << k;
      if (view.geometric & bit || opacity_at(volumes[v], t) > view.presence_threshold) p |= bit;
    }
    return p;
  }

  float opacity_at(const PreparedVolume& v, double t) const {
    return volume_look(v, v.to_index(ray.at(static_cast<float>(t)))).a;  // no data: 0
  }

  bool value(PrimitiveMask present) const { return evaluate(view.program, present); }
};

// Premultiplied RGBA seen along `ray`. `surfaces` are the ray's fragments sorted by t;
// `volumes` at most kMaxRayVolumes (the caller checks). A volume that clip geometry restricts
// (`filter`) is sampled only in the pieces the ray keeps of it: the walk is cut at their ends as
// at the volume's entry and exit. With `csg`, the expression decides
// which samples of its primitives show and which of their surfaces are drawn (SPEC §8): a
// piece shows its CSG volumes and interior media where the expression holds at its midpoint,
// a group of CSG surfaces is drawn where the expression's value differs either side of it.
inline glm::vec4 trace_reference(const Ray& ray, std::span<const Fragment> surfaces,
                                 std::span<const PreparedVolume> volumes,
                                 std::span<const ShadingLight> lights, const ReferenceParams& p,
                                 const CsgView* csg = nullptr, VolumeFilter filter = {}) {
  // Every volume may show: the reference builds no skipping structures.
  const RayVolumes rv(ray, volumes, p.step, p.iso_bisections, lights,
                      VolumeFilter(kEveryVolume, filter.clip));
  std::optional<ReferenceCsg> cs;
  if (csg) cs.emplace(*csg, rv, volumes, ray, surfaces);
  auto in_csg = [&](int v) { return csg && csg->primitive_of_volume[v] >= 0; };

  size_t si = 0;
  int ii = 0;
  auto next_surface_t = [&]() {
    double ts = si < surfaces.size() ? surfaces[si].t : INFINITY;
    return ii < rv.hit_count ? std::min(ts, rv.hits[ii].t) : ts;
  };

  glm::vec4 acc(0.0f);
  double t = 0.0;
  while (acc.a < p.ert) {
    double ts = next_surface_t();
    double boundary = INFINITY;
    bool active = cs && (cs->windings.inside & csg->with_medium) != 0;
    for (int k = 0; k < rv.count; ++k) {
      // A CSG volume's span ends change what is present even where it shows nothing.
      if (!rv.marched[k] && !(in_csg(k) && !rv.span[k].empty())) continue;
      const KeptSpan kept = rv.kept(k);
      for (int i = 0; i < kept.size(); ++i) {
        const RayInterval piece = kept[i];
        if (t < piece.t0) {
          boundary = std::min<double>(boundary, piece.t0);
          break;
        }
        if (t < piece.t1) {
          boundary = std::min<double>(boundary, piece.t1);
          active |= rv.marched[k];
          break;
        }
      }
    }
    double t_next = std::min(ts, boundary);
    if (active) {
      double grid = (std::floor(t / p.step) + 1.0) * p.step;
      if (grid <= t) grid = t + p.step;
      t_next = std::min(t_next, grid);
      double len = t_next - t;
      if (len > 0.0) {
        double m = t + 0.5 * len;
        const PrimitiveMask present = cs ? cs->present(m, m) : 0;
        const bool shows = cs && cs->value(present);
        detail::M1Mix mix;
        detail::ExclusiveMix exclusive;
        const float flen = static_cast<float>(len);
        auto add = [&](const glm::vec4& c, uint8_t rank, float unit) {
          if (p.mixing.exclusive)
            exclusive.add(c, rank, correct_opacity(p.mixing.threshold, flen, unit));
          else
            mix.add(c);
        };
        for (int k = 0; k < rv.count; ++k)
          if (rv.marched[k] && rv.kept(k).contains(m) &&
              (!in_csg(k) || (shows && present >> csg->primitive_of_volume[k] & 1u)))
            add(classify_sample(volumes[k], ray, m, len, lights),
                p.mixing.exclusive ? p.mixing.rank[k] : 0, volumes[k].lut.unit_distance());
        if (shows)
          for (PrimitiveMask media = present & csg->with_medium; media; media &= media - 1) {
            const CsgMedium& medium = csg->medium[std::countr_zero(media)];
            const float a = correct_opacity(medium.opacity, flen, medium.unit_distance);
            add(glm::vec4(medium.color * a, a), p.mixing.medium_rank, medium.unit_distance);
          }
        detail::composite(acc, p.mixing.exclusive ? exclusive.result() : mix.result());
      }
    }
    if (t_next == INFINITY) break;
    t = t_next;
    // Composite every surface at this depth; co-located ones are mixed, not ordered.
    if (ts <= t) {
      detail::M1Mix mix, csg_mix;
      const PrimitiveMask before = cs ? cs->present(ts - p.coincide, ts) : 0;
      double group_end = ts;
      while (next_surface_t() <= ts + p.coincide) {
        if (ii < rv.hit_count && (si >= surfaces.size() || rv.hits[ii].t <= surfaces[si].t)) {
          mix.add(rv.hits[ii++].color);
        } else {
          const Fragment& f = surfaces[si++];
          group_end = f.t;
          if (cs && cs->windings.pass(f, csg->primitive_of_object))
            csg_mix.add(f.color);
          else
            mix.add(f.color);
        }
      }
      if (cs && cs->value(before) != cs->value(cs->present(group_end + p.coincide, ts)))
        mix.merge(csg_mix);
      detail::composite(acc, mix.result());
    }
  }
  return acc;
}

}  // namespace imx
