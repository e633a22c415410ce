// k+-buffer kernel (SPEC §6): a pixel's fragments stored in arrival order into k slots and a
// tail, with or without OFM merging, resolved front to back and intermixed with the volumes.
#pragma once
#include <span>

#include <glm/vec4.hpp>

#include "frame/hybrid_composite.hpp"
#include "frame/surface_thickness.hpp"
#include "methods/fragment/kplus_buffer.hpp"

namespace imx {

// `resolved` holds at least kMaxKBufferSize + 1 slabs.
struct KBufferScratch {
  std::span<Slab> resolved;
  HybridScratch hybrid;
};

// `fragments`: the sample's fragments in arrival (primitive) order.
inline glm::vec4 trace_kbuffer(const Ray& ray, std::span<const Fragment> fragments,
                               const SurfaceThickness& thickness,
                               std::span<const PreparedVolume> volumes,
                               std::span<const ShadingLight> lights, const HybridParams& hp,
                               const KPlusSettings& p, const KBufferScratch& s,
                               VolumeFilter filter = {}) {
  KPlusBuffer buffer(p);
  for (const Fragment& f : fragments) buffer.insert(thickness.slab(f));
  std::span<const Slab> surfaces = s.resolved.first(buffer.resolve(s.resolved));
  const RayVolumes rv(ray, volumes, hp.step, hp.iso_bisections, lights, filter);
  return composite_hybrid(ray, surfaces, rv, volumes, lights, hp, s.hybrid);
}

}  // namespace imx
