// Dynamic fragment buffer kernels (SPEC §6): every fragment of a pixel sorted, then composited
// exactly (`dfb`, the multi-fragment ground truth) or merged by SFM to at most M slabs in the
// resolve pass (`dfb-sfm`); either way intermixed on the fly with the ray's volumes. Pure.
#pragma once
#include <span>

#include <glm/vec4.hpp>

#include "frame/hybrid_composite.hpp"
#include "frame/surface_thickness.hpp"
#include "methods/fragment/dynamic_fragment_buffer.hpp"
#include "slab/resolve_merge.hpp"

namespace imx {

struct DfbParams {
  int cap = kDefaultFragmentCap;  // fragments stored per pixel (render.fragment_cap)
  bool merge = false;             // SFM resolve merge (dfb-sfm)
  int layers = 8;                 // M: merged slabs written back per pixel (render.layers)
};

// Scratch for one ray: `fragments` holds at least `cap` slabs, `merged` at least `layers`.
struct DfbScratch {
  std::span<Slab> fragments, merged;
  HybridScratch hybrid;
};

// `fragments`: the sample's fragments in arrival order (sorted here, in place).
inline glm::vec4 trace_dfb(const Ray& ray, std::span<Fragment> fragments,
                           const SurfaceThickness& thickness,
                           std::span<const PreparedVolume> volumes,
                           std::span<const ShadingLight> lights, const HybridParams& hp,
                           const DfbParams& p, const DfbScratch& s, VolumeFilter filter = {}) {
  std::span<Fragment> sorted = dfb_sort(fragments, std::min<int>(p.cap, int(s.fragments.size())));
  for (size_t i = 0; i < sorted.size(); ++i) s.fragments[i] = thickness.slab(sorted[i]);
  std::span<const Slab> surfaces = s.fragments.first(sorted.size());
  if (p.merge) {
    std::span<Slab> out = s.merged.first(std::min<size_t>(std::max(p.layers, 1), s.merged.size()));
    surfaces = out.first(resolve_merge(surfaces, out, hp.interpolation));
  }
  const RayVolumes rv(ray, volumes, hp.step, hp.iso_bisections, lights, filter);
  return composite_hybrid(ray, surfaces, rv, volumes, lights, hp, s.hybrid);
}

}  // namespace imx
