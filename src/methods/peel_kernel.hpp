// Depth peeling kernel (SPEC §7, seed 001): the first L layers of a pixel, each the nearest
// fragment strictly behind the previous layer (on equal depths the first in scene order wins the
// depth test, as on a GPU), with the volume segments between them ray-cast. Fragments behind the
// last layer are lost, or blended in arrival order by one more pass. As in seed 001, a segment ends
// where the depth test fails for a sample: whole steps are cast and each layer is composited at the
// step boundary nearest to it (`dfb` cuts the steps exactly at each surface). Pure.
#pragma once
#include <algorithm>
#include <cmath>
#include <span>

#include <glm/vec4.hpp>

#include "fragments/dynamic_fragment_buffer.hpp"
#include "methods/hybrid_composite.hpp"

namespace imx {

// Where seed 001's per-sample depth test puts a layer at depth t: the boundary nearest t of the
// step that holds it, for each volume marched there (steps are the cells of the grid k * step,
// cut at the ends of the pieces the ray keeps of the volume, as VolumeMarcher takes them);
// outside every kept piece, t.
inline float nearest_step_boundary(const RayVolumes& rv, float t, float step) {
  double best = t, best_distance = INFINITY;
  const double cell = grid_cell(t, step);
  for (int v = 0; v < rv.count; ++v) {
    if (!rv.marched[v]) continue;
    const KeptSpan kept = rv.kept(v);
    for (int i = 0; i < kept.size(); ++i) {
      const RayInterval piece = kept[i];
      if (!(t > piece.t0 && t < piece.t1)) continue;
      for (double b : {std::max<double>(piece.t0, cell * step),
                       std::min<double>(piece.t1, (cell + 1.0) * step)})
        if (std::abs(b - t) < best_distance) {
          best = b;
          best_distance = std::abs(b - t);
        }
    }
  }
  return static_cast<float>(best);
}

struct PeelParams {
  int layers = 4;              // L, the depth-peeling passes
  bool unsorted_rest = false;  // composite the fragments behind layer L-1 unsorted, or lose them
};

// `layers` holds at least L + 1 slabs. `fragments` are in arrival order.
inline glm::vec4 trace_peel(const Ray& ray, std::span<const Fragment> fragments,
                            const PeelParams& pp, std::span<const PreparedVolume> volumes,
                            std::span<const ShadingLight> lights, const HybridParams& hp,
                            std::span<Slab> layers, const HybridScratch& scratch,
                            VolumeFilter filter = {}) {
  const size_t max_layers =
      std::min<size_t>(std::max(pp.layers, 0), std::max<size_t>(layers.size(), 1) - 1);
  size_t n = 0;
  const Fragment* last = nullptr;
  while (n < max_layers) {  // one pass: the nearest fragment strictly behind the last layer
    const Fragment* nearest = nullptr;
    for (const Fragment& f : fragments)
      if ((!last || f.t > last->t) && (!nearest || fragment_before(f, *nearest))) nearest = &f;
    if (!nearest) break;
    layers[n++] = Slab{nearest->t, 0.0f, nearest->color};
    last = nearest;
  }
  if (pp.unsorted_rest && last) {  // one more pass blends the rest in arrival order, at its front
    glm::vec4 rest(0.0f);
    float front = INFINITY;
    for (const Fragment& f : fragments)
      if (f.t > last->t) {
        rest = over(rest, f.color);
        front = std::min(front, f.t);
      }
    if (front < INFINITY) layers[n++] = Slab{front, 0.0f, rest};
  }
  const RayVolumes rv(ray, volumes, hp.step, hp.iso_bisections, lights, filter);
  for (Slab& layer : layers.first(n))
    layer.t_back = nearest_step_boundary(rv, layer.t_back, hp.step);
  return composite_hybrid(ray, layers.first(n), rv, volumes, lights, hp, scratch);
}

}  // namespace imx
