// The MDVR kernel (SPEC §3): conventional on-the-fly intermixing, the baseline the slab methods
// improve on. Every volume's slab stream is cut on one common grid (VolumeMarcher), the slabs of
// one grid step are mixed (M1) and composited together; a surface is composited whole before the
// first step that starts at or behind it (a binary depth test, no splitting). Pure: no allocation.
#pragma once
#include <cmath>
#include <new>
#include <span>
#include <type_traits>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "raster/fragment.hpp"
#include "slab/mix.hpp"
#include "slab/over.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/ray_volumes.hpp"
#include "volume/volume_marcher.hpp"

namespace imx {

struct MdvrParams {
  float step = 1.0f;  // common step, mm: the smallest voxel pitch of the volumes by default
  float ert = 0.99f;  // early ray termination opacity
  int iso_bisections = 10;
};

// The nearest back depth among the `n` heads that are `live` (INFINITY when none is): the end of
// the grid step the mdvr-style loops take next.
inline float nearest_back(const Slab* heads, const bool* live, int n) {
  float back = INFINITY;
  for (int m = 0; m < n; ++m)
    if (live[m]) back = std::min(back, heads[m].t_back);
  return back;
}

// The steps of several volumes: each marcher holds its next slab (a pending head); the heads that
// lie in the nearest grid step are mixed (M1) and composited together. The conventional method
// knows only the grid steps, so its marchers emit whole pieces (SlabExtent::grid).
template <class SurfacesUntil>
void composite_steps_of_several(const Ray& ray, const RayVolumes& rv,
                                std::span<const PreparedVolume> volumes,
                                std::span<const ShadingLight> lights, const MdvrParams& p,
                                glm::vec4& acc, SurfacesUntil& composite_surfaces_until) {
  // Marchers are built only for the volumes this ray meets: constructing all kMaxRayVolumes
  // (392 B each) up front cost more than marching on two-volume scenes.
  static_assert(std::is_trivially_destructible_v<VolumeMarcher>);
  alignas(VolumeMarcher) unsigned char storage[kMaxRayVolumes * sizeof(VolumeMarcher)];
  VolumeMarcher* marchers = reinterpret_cast<VolumeMarcher*>(storage);
  Slab heads[kMaxRayVolumes];
  bool live[kMaxRayVolumes] = {};
  int n = 0;
  for (int v = 0; v < rv.count; ++v) {
    if (!rv.marched[v]) continue;
    new (&marchers[n]) VolumeMarcher(volumes[v], ray, rv.kept(v), p.step, lights, SlabExtent::grid);
    live[n] = marchers[n].next(heads[n]);
    ++n;
  }
  glm::vec4 step_colors[kMaxRayVolumes];
  while (acc.a < p.ert) {
    const float back = nearest_back(heads, live, n);
    if (back == INFINITY) break;
    const float same_step = back - 1e-3f * p.step;
    float front = back;
    int k = 0;
    // A head thinner than the tolerance (a span may end just past a grid point) is taken when
    // it ends the step, so that every round consumes one and the loop ends.
    for (int m = 0; m < n; ++m)
      if (live[m] && (heads[m].front() < same_step || heads[m].t_back <= back)) {
        front = std::min(front, heads[m].front());
        step_colors[k++] = heads[m].color;
        live[m] = marchers[m].next(heads[m]);
      }
    composite_surfaces_until(front);
    if (acc.a >= p.ert) break;
    acc = over(acc, mix_m1(std::span<const glm::vec4>(step_colors, k)));
  }
}

// A ray's surfaces and volume hits (iso, projections), composited in depth order whole before
// the first step behind them: the binary depth test of mdvr and of the kernels built on it.
struct SurfacesInDepthOrder {
  std::span<const Fragment> surfaces;  // by depth
  const RayVolumes& rv;
  size_t si = 0;
  int hi = 0;

  // Composites every surface and hit not behind depth `t`, while `acc` is below `ert`.
  void composite_until(double t, glm::vec4& acc, float ert) {
    while (acc.a < ert) {
      bool has_s = si < surfaces.size() && surfaces[si].t <= t;
      bool has_h = hi < rv.hit_count && rv.hits[hi].t <= t;
      if (!has_s && !has_h) break;
      if (has_h && (!has_s || rv.hits[hi].t <= surfaces[si].t))
        acc = over(acc, rv.hits[hi++].color);
      else
        acc = over(acc, surfaces[si++].color);
    }
  }
};

inline glm::vec4 trace_mdvr(const Ray& ray, std::span<const Fragment> surfaces,
                            std::span<const PreparedVolume> volumes,
                            std::span<const ShadingLight> lights, const MdvrParams& p,
                            VolumeFilter filter = {}) {
  const RayVolumes rv(ray, volumes, p.step, p.iso_bisections, lights, filter);

  glm::vec4 acc(0.0f);
  SurfacesInDepthOrder in_order{surfaces, rv};
  auto composite_surfaces_until = [&](double t) { in_order.composite_until(t, acc, p.ert); };

  int marched = 0, only = 0;
  for (int v = 0; v < rv.count; ++v)
    if (rv.marched[v]) {
      ++marched;
      only = v;
    }
  if (marched == 1) {
    // One volume: its slabs are the grid steps, nothing to mix.
    VolumeMarcher m(volumes[only], ray, rv.kept(only), p.step, lights, SlabExtent::grid);
    if (surfaces.empty() && rv.hit_count == 0) {
      m.composite(acc, p.ert);  // nothing to interleave: the march runs in one call
    } else {
      Slab s;
      while (acc.a < p.ert && m.next(s)) {
        composite_surfaces_until(s.front());
        if (acc.a >= p.ert) break;
        acc = over(acc, s.color);
      }
    }
  } else if (marched > 1) {
    composite_steps_of_several(ray, rv, volumes, lights, p, acc, composite_surfaces_until);
  }
  composite_surfaces_until(INFINITY);
  return acc;
}

}  // namespace imx
