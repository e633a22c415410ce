// ZslabFrame's object-level split of a deferred stage (SPEC §4, reuse): the object's own slab
// array and its merge into the stored array, so a kept own array can be merged again later.
#include <algorithm>

#include "methods/zslab/zslab_frame.hpp"
#include "methods/zslab/zslab_object_kernel.hpp"

namespace imx {

int ZslabFrame::own_capacity(size_t k) const {
  const ZslabStage& st = stages[k];
  if (st.kind == ZslabStage::Kind::volume) return params.layers;
  int slots = 0;
  for (uint32_t o : st.objects)  // the rasterizer is watertight: a plane has one fragment a ray
    slots += scene.order[o].kind == ObjectKind::plane ? 1 : std::max(params.peel_layers, 1);
  return slots <= kMaxOwnSurfaceSlabs ? slots : 0;
}

int ZslabFrame::own_slabs(size_t k, int x, int y, const Ray& ray,
                          std::span<const Fragment> fragments, std::span<Slab> own,
                          std::span<const Fragment> clip) const {
  const ZslabStage& st = stages[k];
  if (st.kind == ZslabStage::Kind::surfaces) {
    StageThickness th{st.thickness, footprint_at_0_, footprint_per_mm_};
    return peel_surface_slabs(fragments, th, params.peel_layers, own);
  }
  // A volume stage intermixed with nothing emits its own folded slabs unchanged: run_deferred
  // stays the one place that casts a volume.
  SlabList out(own.first(std::min(own.size(), static_cast<size_t>(params.layers))));
  if (!run_deferred(k, x, y, ray, {}, {}, out, clip)) return 0;
  return out.size();
}

bool ZslabFrame::merge_own(size_t k, std::span<const Slab> stored, std::span<const Slab> own,
                           SlabList& out) const {
  if (own.empty()) return false;
  if (stages[k].kind == ZslabStage::Kind::surfaces)
    return merge_surface_slabs(own, stored, out, params);
  intermix_stage(stored, own, out, params.mix);
  return true;
}

}  // namespace imx
