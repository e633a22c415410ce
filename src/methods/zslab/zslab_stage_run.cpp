// ZslabFrame's object-level split of a deferred stage (SPEC §4, reuse): the object's own slab
// array and its merge into the stored array, so a kept own array can be merged again later.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "methods/zslab/zslab_frame.hpp"
#include "methods/zslab/zslab_object_kernel.hpp"
#include "volume/packet_marcher.hpp"

namespace imx {

int ZslabFrame::own_capacity(size_t k) const {
  const ZslabStage& st = stages[k];
  if (st.kind == ZslabStage::Kind::volume) return params.layers;
  // The rasterizer is watertight: a plane has one fragment a ray; others their peel limit.
  int64_t slots = 0;
  for (size_t i = 0; i < st.objects.size(); ++i)
    slots += scene.order[st.objects[i]].kind == ObjectKind::plane ? 1 : std::max(st.peel[i], 1);
  return slots <= kMaxOwnSurfaceSlabs ? static_cast<int>(slots) : 0;
}

int ZslabFrame::own_slabs(size_t k, int x, int y, const Ray& ray,
                          std::span<const Fragment> fragments, std::span<Slab> own,
                          std::span<const Fragment> clip) const {
  const ZslabStage& st = stages[k];
  if (st.kind == ZslabStage::Kind::surfaces) {
    StageThickness th{st.thickness, footprint_at_0_, footprint_per_mm_};
    return peel_surface_slabs(fragments, th, params.peel_layers, own, st.peel);
  }
  // A volume stage intermixed with nothing emits its own folded slabs unchanged: run_deferred
  // stays the one place that casts a volume.
  SlabList out(own.first(std::min(own.size(), static_cast<size_t>(params.layers))));
  if (!run_deferred(k, x, y, ray, {}, {}, out, clip)) return 0;
  return out.size();
}

namespace {

// Volume stage `k` of `z` can march in lanes: dvr, no label map, no clip mesh cutting it.
bool casts_in_lanes(const ZslabFrame& z, size_t k) {
  const ZslabStage& st = z.stages[k];
  if (st.kind != ZslabStage::Kind::volume || !z.scene.render.packets ||
      z.frame.clip.clips(static_cast<size_t>(st.volume)))
    return false;
  const PreparedVolume& v = z.frame.volumes[static_cast<size_t>(st.volume)];
  return v.object->style == VolumeStyle::dvr && !v.labels.active() &&
         packet_marching_supported(v, z.frame.lights);
}

// The samples of `tile` (for_each_sample's order) whose rays meet volume `volume` where it may
// show, and those rays (PreparedVolume::intersect's span): what run_deferred and run_final cast.
void rays_of_tile(const ZslabFrame& z, int volume, const TileRect& tile,
                  std::vector<PacketRay>& rays, std::vector<size_t>& sample) {
  const PreparedVolume& v = z.frame.volumes[static_cast<size_t>(volume)];
  size_t i = 0;
  for (int y = tile.y0; y < tile.y1; ++y)
    for (int x = tile.x0; x < tile.x1; ++x)
      for (const glm::vec2& o : z.offsets) {
        if (v.lut.max_opacity() > 0.0f && z.frame.may_show(volume, x, y)) {
          rays.push_back({z.frame.camera.ray(x + o.x, y + o.y)});
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
  sample.resize(kept);
}

}  // namespace

bool ZslabFrame::volume_stage_in_packets(size_t k) const {
  return !stages[k].on_the_fly && casts_in_lanes(*this, k);
}

bool ZslabFrame::final_stage_in_lanes(size_t k) const {
  return k < stages.size() && stages[k].on_the_fly && casts_in_lanes(*this, k);
}

void ZslabFrame::run_final_in_lanes(size_t k, const TileRect& tile,
                                    std::span<const std::span<const Slab>> stored,
                                    std::span<glm::vec4> out) const {
  for (size_t i = 0; i < stored.size(); ++i) out[i] = accumulate(stored[i], params.mix.a_ert).color;
  std::vector<PacketRay> rays;
  std::vector<size_t> sample;
  rays_of_tile(*this, stages[k].volume, tile, rays, sample);
  // trace_hybrid for every cast sample: its slabs through the kernel against its stored array.
  struct Kernels final : SlabSink {
    DiscardSink discard;
    std::vector<Intermixer<DiscardSink>> of_ray;
    bool take(size_t ray, const Slab& slab) override { return of_ray[ray].push(slab); }
  } kernels;
  kernels.of_ray.reserve(rays.size());
  for (size_t s : sample) kernels.of_ray.emplace_back(stored[s], kernels.discard, params.mix);
  const PreparedVolume& v = frame.volumes[static_cast<size_t>(stages[k].volume)];
  march_slab_packets(v, rays, stages[k].step, frame.lights, 2.0f, kernels);  // no ERT of its own
  for (size_t j = 0; j < sample.size(); ++j) {
    kernels.of_ray[j].finish();
    out[sample[j]] = kernels.of_ray[j].accumulated();
  }
}

void ZslabFrame::own_volume_slabs(size_t k, const TileRect& tile, std::span<SlabList> lists) const {
  for (SlabList& list : lists) list.clear();
  std::vector<PacketRay> rays;
  std::vector<size_t> sample;
  rays_of_tile(*this, stages[k].volume, tile, rays, sample);
  std::vector<SlabList> cast;
  cast.reserve(sample.size());
  for (size_t s : sample) cast.push_back(lists[s]);
  const PreparedVolume& v = frame.volumes[static_cast<size_t>(stages[k].volume)];
  collect_packets(v, rays, stages[k].step, frame.lights, params.mix.a_ert,
                  SlabCollection{cast, params.mix.overflow});
  for (size_t j = 0; j < sample.size(); ++j) lists[sample[j]] = cast[j];
}

bool ZslabFrame::merge_own(size_t k, std::span<const Slab> stored, std::span<const Slab> own,
                           SlabList& out) const {
  return run_wide_scalar(wide_, [&] {
    if (own.empty()) return false;
    if (stages[k].kind == ZslabStage::Kind::surfaces)
      return merge_surface_slabs(own, stored, out, params);
    intermix_stage(stored, own, out, params.mix);
    return true;
  });
}

}  // namespace imx
