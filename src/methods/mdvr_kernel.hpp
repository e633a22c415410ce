// The MDVR kernel (SPEC §3): conventional on-the-fly intermixing, the baseline the slab methods
// improve on. All volumes are sampled together at one step (a sample at t stands for [t, t+step)); a surface is composited whole before
// the first sample behind it (a binary depth test, no splitting). Pure: no allocation.
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
#include "volume/iso_crossing.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

inline constexpr int kMaxMdvrVolumes = 16;

struct MdvrParams {
  double step = 1.0;  // common step, mm: the smallest voxel pitch of the volumes by default
  float ert = 0.99f;  // early ray termination opacity
  int iso_bisections = 10;
};

inline glm::vec4 trace_mdvr(const Ray& ray, std::span<const Fragment> surfaces,
                            std::span<const PreparedVolume> volumes,
                            std::span<const ShadingLight> lights, const MdvrParams& p) {
  RayInterval span_of[kMaxMdvrVolumes];
  bool marched[kMaxMdvrVolumes] = {};
  IsoHit iso_hits[kMaxMdvrVolumes];
  int iso_count = 0;
  int nv = static_cast<int>(std::min<size_t>(volumes.size(), kMaxMdvrVolumes));
  double t_first = INFINITY, t_last = -INFINITY;
  for (int k = 0; k < nv; ++k) {
    const PreparedVolume& v = volumes[k];
    span_of[k] = v.intersect(ray);
    if (span_of[k].empty()) continue;
    if (v.object->style == VolumeStyle::iso) {
      IsoHit h;
      if (find_iso_crossing(v, ray, span_of[k].t0, span_of[k].t1, p.step, p.iso_bisections, lights,
                            h))
        iso_hits[iso_count++] = h;
    } else if (v.lut.max_opacity() > 0.0f) {
      marched[k] = true;
      t_first = std::min<double>(t_first, span_of[k].t0);
      t_last = std::max<double>(t_last, span_of[k].t1);
    }
  }
  std::sort(iso_hits, iso_hits + iso_count,
            [](const IsoHit& a, const IsoHit& b) { return a.t < b.t; });

  size_t si = 0;
  int ii = 0;
  glm::vec4 acc(0.0f);
  // Composites, in depth order, every surface and iso hit not behind depth `t`.
  auto composite_surfaces_until = [&](double t) {
    while (acc.a < p.ert) {
      bool has_s = si < surfaces.size() && surfaces[si].t <= t;
      bool has_i = ii < iso_count && iso_hits[ii].t <= t;
      if (!has_s && !has_i) break;
      if (has_i && (!has_s || iso_hits[ii].t <= surfaces[si].t))
        acc = over(acc, iso_hits[ii++].color);
      else
        acc = over(acc, surfaces[si++].color);
    }
  };

  if (t_first < t_last) {
    glm::vec4 samples[kMaxMdvrVolumes];
    for (double k = std::ceil(t_first / p.step); acc.a < p.ert; k += 1.0) {
      double t = k * p.step;
      if (t >= t_last) break;
      composite_surfaces_until(t);
      int n = 0;
      for (int v = 0; v < nv; ++v)
        if (marched[v] && span_of[v].t0 <= t && t < span_of[v].t1)
          samples[n++] = classify_sample(volumes[v], ray, t, p.step, lights);
      if (n > 0) acc = over(acc, mix_m1(std::span<const glm::vec4>(samples, n)));
    }
  }
  composite_surfaces_until(INFINITY);
  return acc;
}

}  // namespace imx
