// Depth peeling kernel (SPEC §7): the first L layers of a pixel, each the nearest fragment
// strictly behind the previous layer (on equal depths the first in scene order wins the depth
// test, as on a GPU), with the volume segments between them ray-cast. Fragments behind the last
// layer are lost. Pure.
#pragma once
#include <span>

#include <glm/vec4.hpp>

#include "fragments/dynamic_fragment_buffer.hpp"
#include "methods/hybrid_composite.hpp"

namespace imx {

// `layers` holds at least L slabs. `fragments` arrive in any order and are sorted in place.
inline glm::vec4 trace_peel(const Ray& ray, std::span<Fragment> fragments, int peel_layers,
                            std::span<const PreparedVolume> volumes,
                            std::span<const ShadingLight> lights, const HybridParams& hp,
                            std::span<Slab> layers, const HybridScratch& scratch) {
  std::span<Fragment> sorted = dfb_sort(fragments, int(fragments.size()));
  const size_t max_layers = std::min<size_t>(std::max(peel_layers, 0), layers.size());
  size_t n = 0;
  for (const Fragment& f : sorted) {
    if (n == max_layers) break;
    if (n > 0 && !(f.t > layers[n - 1].t_back)) continue;  // not behind the last peel
    layers[n++] = Slab{f.t, 0.0f, f.color};
  }
  const RayVolumes rv(ray, volumes, hp.step, hp.iso_bisections, lights);
  return composite_hybrid(ray, layers.first(n), rv, volumes, lights, hp, scratch);
}

}  // namespace imx
