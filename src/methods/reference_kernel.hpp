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
#include "volume/classify.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/ray_volumes.hpp"

namespace imx {

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

}  // namespace detail

// Premultiplied RGBA seen along `ray`. `surfaces` are the ray's fragments sorted by t;
// `volumes` at most kMaxRayVolumes (the caller checks).
inline glm::vec4 trace_reference(const Ray& ray, std::span<const Fragment> surfaces,
                                 std::span<const PreparedVolume> volumes,
                                 std::span<const ShadingLight> lights, const ReferenceParams& p) {
  const RayVolumes rv(ray, volumes, p.step, p.iso_bisections, lights);

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
    bool active = false;
    for (int k = 0; k < rv.count; ++k) {
      if (!rv.marched[k]) continue;
      if (t < rv.span[k].t0) {
        boundary = std::min<double>(boundary, rv.span[k].t0);
      } else if (t < rv.span[k].t1) {
        boundary = std::min<double>(boundary, rv.span[k].t1);
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
        for (int k = 0; k < rv.count; ++k)
          if (rv.marched[k] && rv.span[k].t0 <= m && m < rv.span[k].t1)
            mix.add(classify_sample(volumes[k], ray, m, len, lights));
        detail::composite(acc, mix.result());
      }
    }
    if (t_next == INFINITY) break;
    t = t_next;
    // Composite every surface at this depth; co-located ones are mixed, not ordered.
    if (ts <= t) {
      detail::M1Mix mix;
      while (next_surface_t() <= ts + p.coincide) {
        if (ii < rv.hit_count && (si >= surfaces.size() || rv.hits[ii].t <= surfaces[si].t)) {
          mix.add(rv.hits[ii++].color);
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
