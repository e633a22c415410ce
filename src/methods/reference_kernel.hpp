// The reference kernel (SPEC §3): one sample ray through every volume and surface, exactly.
// Written independently of the slab algebra so it can judge it. Pure: no allocation.
#pragma once
#include <algorithm>
#include <cmath>
#include <span>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "raster/fragment.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

inline constexpr int kMaxReferenceVolumes = 16;

struct ReferenceParams {
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
  glm::vec4 result() const {
    float a = 1.0f - transmittance;
    if (alpha_sum <= 0.0f) return glm::vec4(0.0f);
    return glm::vec4(colour_sum / alpha_sum * a, a);
  }
};

struct SurfaceHit {
  double t;
  glm::vec4 color;
};

// First crossing of the iso-value inside [t0, t1], refined by bisection; false when none.
inline bool find_iso_crossing(const PreparedVolume& v, const Ray& ray, double t0, double t1,
                              const ReferenceParams& p, std::span<const ShadingLight> lights,
                              SurfaceHit& hit) {
  float iso = static_cast<float>(v.object->iso_value);
  auto value_at = [&](double t) {
    return v.grid.sample(v.to_index(ray.at(static_cast<float>(t)))) - iso;
  };
  double a = t0;
  float fa = value_at(a);
  while (a < t1) {
    double b = std::min(t1, (std::floor(a / p.step) + 1.0) * p.step);
    if (b <= a) b = std::min(t1, a + p.step);
    float fb = value_at(b);
    if ((fa < 0.0f) != (fb < 0.0f)) {
      double lo = a, hi = b;
      float flo = fa;
      for (int i = 0; i < p.iso_bisections; ++i) {
        double mid = 0.5 * (lo + hi);
        float fm = value_at(mid);
        if ((fm < 0.0f) == (flo < 0.0f)) {
          lo = mid;
          flo = fm;
        } else {
          hi = mid;
        }
      }
      // Linear interpolation inside the final bracket places the surface well below its width.
      float fhi = value_at(hi);
      double t = flo == fhi ? 0.5 * (lo + hi) : lo + (hi - lo) * (flo / (flo - fhi));
      glm::vec3 idx = v.to_index(ray.at(static_cast<float>(t)));
      glm::vec4 tf = v.lut.lookup(iso);
      glm::vec3 rgb =
          blinn_phong(v.object->shading, glm::vec3(tf), v.world_gradient(idx), -ray.dir, lights);
      hit = {t, glm::vec4(rgb * tf.a, tf.a)};
      return true;
    }
    a = b;
    fa = fb;
  }
  return false;
}

// Classified, shaded, premultiplied contribution of volume `v` over a step of length `len`
// sampled at depth `m`.
inline glm::vec4 classify_sample(const PreparedVolume& v, const Ray& ray, double m, double len,
                                 std::span<const ShadingLight> lights) {
  glm::vec3 idx = v.to_index(ray.at(static_cast<float>(m)));
  glm::vec4 tf = v.lut.lookup(v.grid.sample(idx));
  if (tf.a <= 0.0f) return glm::vec4(0.0f);
  float a = correct_opacity(tf.a, static_cast<float>(len), v.lut.unit_distance());
  glm::vec3 rgb(tf);
  if (v.object->shading.enabled)
    rgb = blinn_phong(v.object->shading, rgb, v.world_gradient(idx), -ray.dir, lights);
  return glm::vec4(rgb * a, a);
}

}  // namespace detail

// Premultiplied RGBA seen along `ray`. `surfaces` are the ray's fragments sorted by t;
// `volumes` at most kMaxReferenceVolumes (the caller checks).
inline glm::vec4 trace_reference(const Ray& ray, std::span<const Fragment> surfaces,
                                 std::span<const PreparedVolume> volumes,
                                 std::span<const ShadingLight> lights, const ReferenceParams& p) {
  using detail::SurfaceHit;
  RayInterval span_of[kMaxReferenceVolumes];
  bool marched[kMaxReferenceVolumes] = {};
  SurfaceHit iso_hits[kMaxReferenceVolumes];
  int iso_count = 0;
  int nv = static_cast<int>(std::min<size_t>(volumes.size(), kMaxReferenceVolumes));
  for (int k = 0; k < nv; ++k) {
    const PreparedVolume& v = volumes[k];
    span_of[k] = v.intersect(ray);
    if (span_of[k].empty()) continue;
    if (v.object->style == VolumeStyle::iso) {
      SurfaceHit h;
      if (detail::find_iso_crossing(v, ray, span_of[k].t0, span_of[k].t1, p, lights, h))
        iso_hits[iso_count++] = h;
    } else {
      marched[k] = v.lut.max_opacity() > 0.0f;
    }
  }
  std::sort(iso_hits, iso_hits + iso_count,
            [](const SurfaceHit& a, const SurfaceHit& b) { return a.t < b.t; });

  size_t si = 0;
  int ii = 0;
  auto next_surface_t = [&]() {
    double ts = si < surfaces.size() ? surfaces[si].t : INFINITY;
    return ii < iso_count ? std::min(ts, iso_hits[ii].t) : ts;
  };

  glm::vec4 acc(0.0f);
  double t = 0.0;
  while (acc.a < p.ert) {
    double ts = next_surface_t();
    double boundary = INFINITY;
    bool active = false;
    for (int k = 0; k < nv; ++k) {
      if (!marched[k]) continue;
      if (t < span_of[k].t0) {
        boundary = std::min<double>(boundary, span_of[k].t0);
      } else if (t < span_of[k].t1) {
        boundary = std::min<double>(boundary, span_of[k].t1);
        active = true;
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
        detail::M1Mix mix;
        for (int k = 0; k < nv; ++k)
          if (marched[k] && span_of[k].t0 <= m && m < span_of[k].t1)
            mix.add(detail::classify_sample(volumes[k], ray, m, len, lights));
        detail::composite(acc, mix.result());
      }
    }
    if (t_next == INFINITY) break;
    t = t_next;
    // Composite every surface at this depth; co-located ones are mixed, not ordered.
    if (ts <= t) {
      detail::M1Mix mix;
      while (next_surface_t() <= ts + p.coincide) {
        if (ii < iso_count && (si >= surfaces.size() || iso_hits[ii].t <= surfaces[si].t)) {
          mix.add(iso_hits[ii++].color);
        } else {
          mix.add(surfaces[si++].color);
        }
      }
      detail::composite(acc, mix.result());
    }
  }
  return acc;
}

}  // namespace imx
