// Depth peeling kernel (SPEC §7, seed 001): opaque fragments go into an ordinary depth buffer (the
// nearest one per sample), and only the transparent fragments in front of it are peeled: the
// first L layers of a sample, each the nearest transparent fragment strictly behind the previous
// layer (on equal depths the first in scene order wins the depth test, as on a GPU), with the
// volume segments between them ray-cast. Transparent fragments behind the last layer are lost, or
// blended in arrival order by one more pass; the opaque fragment is composited last and ends the
// ray. As in seed 001, a segment ends where the depth test fails for a sample: whole steps are
// cast and each layer is composited at the step boundary nearest to it (`dfb` cuts the steps
// exactly at each surface). Pure.
#pragma once
#include <algorithm>
#include <cmath>
#include <span>

#include <glm/vec4.hpp>

#include "frame/hybrid_composite.hpp"
#include "methods/fragment/dynamic_fragment_buffer.hpp"

namespace imx {

// A fragment hides everything behind it when its premultiplied opacity is 1: a mesh or plane of
// opacity 1 (shading premultiplies by the material's opacity, so its alpha is exactly 1).
inline bool is_opaque(const Fragment& f) {
  return f.color.a >= 1.0f;
}

// The depth buffer of the opaque pass: the nearest opaque fragment, in the depth order of
// fragment_before; null when the sample has none.
inline const Fragment* nearest_opaque(std::span<const Fragment> fragments) {
  const Fragment* nearest = nullptr;
  for (const Fragment& f : fragments)
    if (is_opaque(f) && (!nearest || fragment_before(f, *nearest))) nearest = &f;
  return nearest;
}

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

// The opaque depth ends the ray: volumes are marched only up to `t`, and volume hits behind it
// (iso surfaces, projections) are hidden.
inline void end_volumes_at(RayVolumes& rv, float t) {
  for (int v = 0; v < rv.count; ++v) {
    rv.span[v].t1 = std::min(rv.span[v].t1, t);
    if (rv.kept(v).empty()) rv.marched[v] = false;
  }
  while (rv.hit_count > 0 && rv.hits[rv.hit_count - 1].t > t) --rv.hit_count;
}

struct PeelParams {
  int layers = 4;              // L, the depth-peeling passes of the transparent fragments
  bool unsorted_rest = false;  // composite the transparent fragments behind layer L-1 unsorted
};

// A sample's fragments after the depth test against the opaque pass.
struct DepthTested {
  std::span<const Fragment> transparent;  // in front of the opaque fragment, in arrival order
  bool has_opaque = false;
  Fragment opaque;  // the nearest opaque fragment, when there is one
};

// Keeps the transparent fragments in front of the nearest opaque one at the front of `row`, in
// arrival order, overwriting the others; without an opaque fragment `row` is left as it is.
inline DepthTested depth_test_opaque(std::span<Fragment> row) {
  const Fragment* nearest = nearest_opaque(row);
  if (!nearest) return {row, false, {}};
  const Fragment opaque = *nearest;
  size_t kept = 0;
  for (size_t i = 0; i < row.size(); ++i)
    if (!is_opaque(row[i]) && fragment_before(row[i], opaque)) row[kept++] = row[i];
  return {row.first(kept), true, opaque};
}

// `layers` holds at least L + 2 slabs (L layers, the unsorted rest, the opaque fragment).
// `row`: the sample's fragments in arrival order; the depth test may overwrite them.
inline glm::vec4 trace_peel(const Ray& ray, std::span<Fragment> row, const PeelParams& pp,
                            std::span<const PreparedVolume> volumes,
                            std::span<const ShadingLight> lights, const HybridParams& hp,
                            std::span<Slab> layers, const HybridScratch& scratch,
                            VolumeFilter filter = {}) {
  const size_t max_layers =
      std::min<size_t>(std::max(pp.layers, 0), layers.size() > 2 ? layers.size() - 2 : 0);
  // Only these are peeled: the opaque pass's depth ends every peel pass.
  const DepthTested tested = depth_test_opaque(row);
  const std::span<const Fragment> fragments = tested.transparent;
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
  if (tested.has_opaque) layers[n++] = Slab{tested.opaque.t, 0.0f, tested.opaque.color};
  RayVolumes rv(ray, volumes, hp.step, hp.iso_bisections, lights, filter);
  for (Slab& layer : layers.first(n))
    layer.t_back = nearest_step_boundary(rv, layer.t_back, hp.step);
  if (tested.has_opaque) end_volumes_at(rv, layers[n - 1].t_back);
  return composite_hybrid(ray, layers.first(n), rv, volumes, lights, hp, scratch);
}

}  // namespace imx
