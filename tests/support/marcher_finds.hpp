// Whether the volume marcher finds anything on a ray: what empty-space skipping may never leave
// out.
#pragma once
#include <span>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/volume_marcher.hpp"

namespace imx::test {

inline bool marcher_finds_something(const PreparedVolume& v, const Ray& ray, float step,
                                    std::span<const ShadingLight> lights) {
  const RayInterval span = v.intersect(ray);
  if (span.empty()) return false;
  VolumeMarcher marcher(v, ray, span.t0, span.t1, step, lights);
  Slab first;
  return marcher.next(first);
}

}  // namespace imx::test
