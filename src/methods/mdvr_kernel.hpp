// The MDVR kernel (SPEC §3): conventional on-the-fly intermixing, the baseline the slab methods
// improve on. All volumes are sampled together at one step (a sample at t stands for [t, t+step));
// a surface is composited whole before the first sample behind it (a binary depth test, no
// splitting). Pure: no allocation.
#pragma once
#include <algorithm>
#include <cmath>
#include <span>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "raster/fragment.hpp"
#include "slab/mix.hpp"
#include "slab/over.hpp"
#include "volume/classify.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/ray_volumes.hpp"

namespace imx {

struct MdvrParams {
  double step = 1.0;  // common step, mm: the smallest voxel pitch of the volumes by default
  float ert = 0.99f;  // early ray termination opacity
  int iso_bisections = 10;
};

inline glm::vec4 trace_mdvr(const Ray& ray, std::span<const Fragment> surfaces,
                            std::span<const PreparedVolume> volumes,
                            std::span<const ShadingLight> lights, const MdvrParams& p) {
  const RayVolumes rv(ray, volumes, p.step, p.iso_bisections, lights);

  size_t si = 0;
  int ii = 0;
  glm::vec4 acc(0.0f);
  // Composites, in depth order, every surface and iso hit not behind depth `t`.
  auto composite_surfaces_until = [&](double t) {
    while (acc.a < p.ert) {
      bool has_s = si < surfaces.size() && surfaces[si].t <= t;
      bool has_i = ii < rv.iso_count && rv.iso[ii].t <= t;
      if (!has_s && !has_i) break;
      if (has_i && (!has_s || rv.iso[ii].t <= surfaces[si].t))
        acc = over(acc, rv.iso[ii++].color);
      else
        acc = over(acc, surfaces[si++].color);
    }
  };

  if (rv.t_first < rv.t_last) {
    glm::vec4 samples[kMaxRayVolumes];
    for (double k = std::ceil(rv.t_first / p.step); acc.a < p.ert; k += 1.0) {
      double t = k * p.step;
      if (t >= rv.t_last) break;
      composite_surfaces_until(t);
      int n = 0;
      for (int v = 0; v < rv.count; ++v)
        if (rv.marched[v] && rv.span[v].t0 <= t && t < rv.span[v].t1)
          samples[n++] = classify_sample(volumes[v], ray, t, p.step, lights);
      if (n > 0) acc = over(acc, mix_m1(std::span<const glm::vec4>(samples, n)));
    }
  }
  composite_surfaces_until(INFINITY);
  return acc;
}

}  // namespace imx
