// The ray base (render_per_sample): the orchestration for methods that trace each sample ray
// independently through its depth-sorted fragments (reference, mdvr): the tile base
// (tile_base.hpp) with a stateless per-ray kernel.
#pragma once
#include <span>

#include "frame/tile_base.hpp"

namespace imx {

// `kernel(const Ray&, std::span<const Fragment>, const VolumeFilter&)` returns the premultiplied
// colour of one ray.
template <class Kernel>
Image render_per_sample(const Scene& scene, const FrameSetup& frame, int spp,
                        const RenderOptions& options, const Kernel& kernel) {
  return render_fragment_method(scene, frame, spp, options, FragmentOrder::depth, [&] {
    return [&](const Ray& ray, std::span<Fragment> fragments, const VolumeFilter& filter) {
      return kernel(ray, std::span<const Fragment>(fragments), filter);
    };
  });
}

}  // namespace imx
