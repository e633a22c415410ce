// Hybrid compositing of one ray (SPEC §4, §6 "Hybrid", §7): the surface slabs a fragment method
// resolved for a pixel, intermixed with the ray's volumes. Volume hits (iso, mip, xray) join the
// surfaces first; every marched volume but the last is intermixed into a stored array, the last
// one on the fly with early ray termination. Zero-thickness surfaces split the volume's slabs
// exactly at their depth: ray-cast segments with the surfaces composited in between.
// Pure: the caller provides the scratch storage; no allocation.
#pragma once
#include <span>

#include <glm/vec4.hpp>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "slab/accumulate.hpp"
#include "slab/intermix_kernel.hpp"
#include "slab/slab_array.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/ray_volumes.hpp"
#include "volume/volume_marcher.hpp"

namespace imx {

struct HybridParams {
  float step = 1.0f;  // volume sampling step, mm
  float ert = kDefaultErtOpacity;
  int iso_bisections = 10;
  InSlabInterpolation interpolation{};
};

// Two slab arrays a stage reads and writes in turn (the ZT ping-pong buffers of one ray).
struct HybridScratch {
  std::span<Slab> a, b;
};

// `surfaces`: sorted, disjoint slabs (not aliasing the scratch). Returns premultiplied RGBA.
inline glm::vec4 composite_hybrid(const Ray& ray, std::span<const Slab> surfaces,
                                  const RayVolumes& rv, std::span<const PreparedVolume> volumes,
                                  std::span<const ShadingLight> lights, const HybridParams& p,
                                  const HybridScratch& scratch) {
  // Stored stages stop at the ERT opacity too: behind it the last stage's own ERT has fired.
  IntermixSettings stored{p.interpolation, p.ert, Overflow::tail, true};
  std::span<const Slab> current = surfaces;
  std::span<Slab> spare = scratch.a, other = scratch.b;
  auto into_spare = [&](auto&& feed) {
    SlabList out(spare);
    Intermixer<SlabList> kernel(current, out, stored);
    feed(kernel);
    kernel.finish();
    current = out.items();
    std::swap(spare, other);
  };

  if (rv.hit_count > 0)
    into_spare([&](auto& kernel) {
      for (int i = 0; i < rv.hit_count; ++i)
        kernel.push(Slab{static_cast<float>(rv.hits[i].t), 0.0f, rv.hits[i].color});
    });

  int last = -1;
  for (int v = 0; v < rv.count; ++v)
    if (rv.marched[v]) last = v;
  for (int v = 0; v < last; ++v) {
    if (!rv.marched[v]) continue;
    into_spare([&](auto& kernel) {
      VolumeMarcher m(volumes[v], ray, rv.kept(v), p.step, lights);
      for (Slab s; m.next(s);)
        if (!kernel.push(s)) break;
    });
  }
  if (last < 0) return accumulate(current, p.ert).color;

  DiscardSink sink;
  IntermixSettings final_stage{p.interpolation, p.ert, Overflow::tail, true};
  Intermixer<DiscardSink> kernel(current, sink, final_stage);
  VolumeMarcher m(volumes[last], ray, rv.kept(last), p.step, lights);
  for (Slab s; m.next(s);)
    if (!kernel.push(s)) break;
  kernel.finish();
  return kernel.accumulated();
}

}  // namespace imx
