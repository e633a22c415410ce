// ZslabFrame's object-level split of a deferred stage (SPEC §4, reuse): the object's own slab
// array and its merge into the stored array, so a kept own array can be merged again later.
#include <algorithm>
#include <vector>

#include "methods/zslab/zslab_frame.hpp"
#include "methods/zslab/zslab_object_kernel.hpp"
#include "volume/packet_marcher.hpp"

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

bool ZslabFrame::volume_stage_in_packets(size_t k) const {
  const ZslabStage& st = stages[k];
  if (st.kind != ZslabStage::Kind::volume || st.on_the_fly || !scene.render.packets ||
      frame.clip.clips(static_cast<size_t>(st.volume)))
    return false;
  const PreparedVolume& v = frame.volumes[static_cast<size_t>(st.volume)];
  return v.object->style == VolumeStyle::dvr && !v.labels.active() &&
         packet_marching_supported(v, frame.lights);
}

void ZslabFrame::own_volume_slabs(size_t k, const TileRect& tile, std::span<SlabList> lists) const {
  const ZslabStage& st = stages[k];
  const PreparedVolume& v = frame.volumes[static_cast<size_t>(st.volume)];
  // The samples run_deferred would cast (those its volume may show in), in order: consecutive
  // samples of a row make coherent packets.
  std::vector<PacketRay> rays;
  std::vector<SlabList> cast;
  std::vector<size_t> sample;
  size_t i = 0;
  for (int y = tile.y0; y < tile.y1; ++y)
    for (int x = tile.x0; x < tile.x1; ++x)
      for (const glm::vec2& o : offsets) {
        lists[i].clear();
        if (v.lut.max_opacity() > 0.0f && frame.may_show(st.volume, x, y)) {
          rays.push_back({frame.camera.ray(x + o.x, y + o.y)});
          sample.push_back(i);
        }
        ++i;
      }
  intersect_packets(v, rays);
  size_t kept = 0;
  for (size_t j = 0; j < rays.size(); ++j)
    if (!RayInterval{rays[j].t0, rays[j].t1}.empty()) {
      rays[kept] = rays[j];
      sample[kept++] = sample[j];
    }
  rays.resize(kept);
  for (size_t j = 0; j < kept; ++j) cast.push_back(lists[sample[j]]);
  collect_packets(v, rays, st.step, frame.lights, params.mix.a_ert,
                  SlabCollection{cast, params.mix.overflow});
  for (size_t j = 0; j < kept; ++j) lists[sample[j]] = cast[j];
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
