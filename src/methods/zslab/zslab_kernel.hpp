// zSlab pipeline kernels for one sample ray (SPEC §4): virtual zSlabs, the RT rearrangement, a
// deferred stage through the intermixing kernel, a volume's compressed slab array, and the hybrid
// on-the-fly cast. Pure: fixed-size arrays on the stack, no allocation, no exceptions.
#pragma once
#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>

#include <glm/vec4.hpp>

#include "intermix/scene.hpp"
#include "raster/fragment.hpp"
#include "slab/accumulate.hpp"
#include "slab/collect_slabs.hpp"
#include "slab/intermix_kernel.hpp"
#include "slab/slab.hpp"
#include "slab/slab_array.hpp"
#include "slab/zslab_params.hpp"

namespace imx {

static_assert(kMaxZslabLayers == RenderSettings::kMaxLayers &&
              kMaxRtLayers == RenderSettings::kMaxLayers);

// Virtual zSlab of a surface at depth t: the slab [t - d, t] (SPEC §4).
inline Slab virtual_slab(float t, float thickness, const glm::vec4& color) {
  return Slab{t, thickness, color};
}

// The rearrangement stage: surface slabs from the RT layers (any order, possibly overlapping
// each other) become a sorted, disjoint list in `out` (capacity >= rt.size()). Each slab is
// intermixed into the list built so far, so overlapping virtual slabs mix (no ERT: the list
// is intermixed again afterwards).
inline void rearrange_layers(std::span<Slab> rt, SlabList& out, InSlabInterpolation interp) {
  for (size_t i = 1; i < rt.size(); ++i)  // insertion sort: M is small
    for (size_t j = i; j > 0 && detail::sorts_before(rt[j], rt[j - 1]); --j)
      std::swap(rt[j], rt[j - 1]);
  SlabScratch<kMaxRtLayers> buf[2];
  int count = 0, cur = 0;
  IntermixSettings s;
  s.interpolation = interp;
  s.a_ert = 1.0f;
  for (const Slab& layer : rt) {
    SlabList next(buf[1 - cur].span());
    intermix(std::span<const Slab>(buf[cur].data(), count), std::span<const Slab>(&layer, 1), next,
             s);
    count = next.size();
    cur = 1 - cur;
  }
  out.clear();
  for (int k = 0; k < count; ++k) out.push_back(buf[cur][k], Overflow::tail);
}

// One deferred stage: intermixes the incoming sorted, disjoint slabs with the stored array into
// `out` (capacity N; overflow folds as the settings say).
inline void intermix_stage(std::span<const Slab> stored, std::span<const Slab> incoming,
                           SlabList& out, const IntermixSettings& s) {
  out.clear();
  intermix(stored, incoming, out, s);
}

// Hybrid stage: the last volume's slabs go through the kernel against the stored array as the
// ray marches, stopping the march when ERT fires. Returns the pixel's premultiplied colour.
template <class Source>
inline glm::vec4 trace_hybrid(std::span<const Slab> stored, Source& source,
                              const IntermixSettings& s) {
  DiscardSink sink;
  Intermixer<DiscardSink> kernel(stored, sink, s);
  Slab q;
  while (source.next(q))
    if (!kernel.push(q)) break;
  kernel.finish();
  return kernel.accumulated();
}

// How a surface stage turns fragments into virtual zSlabs: per object of the stage a fixed
// thickness in mm, or (< 0) the world footprint of one pixel at the fragment's depth.
struct StageThickness {
  std::span<const float> by_object;  // indexed by Fragment::object (the stage's own numbering)
  float footprint_at_0 = 0.0f;       // footprint(t) = footprint_at_0 + footprint_per_mm * t
  float footprint_per_mm = 0.0f;
  float of(uint32_t object, float t) const {
    float d = object < by_object.size() ? by_object[object] : -1.0f;
    return d >= 0.0f ? d : footprint_at_0 + footprint_per_mm * t;
  }
};

// How many fragments of an object a surface stage keeps per ray: by default its first L (the
// depth-peeling passes of a polygon object); `by_object` (indexed by Fragment::object, the
// stage's own numbering) overrides L per object: tubes are ray-traced, not peeled, and keep every
// crossing that can still show.
inline int peel_limit(std::span<const int> by_object, uint32_t object, int layers) {
  return object < by_object.size() ? by_object[object] : layers;
}

// The ping-pong ZT arrays of a surface stage, on the stack: virtual slabs fill the M RT layers,
// and each time they are full (and at the end) the layers are rearranged and intermixed with the
// current array into the other one; the stored array is the first current one. Pure.
class SurfaceStageMerge {
 public:
  SurfaceStageMerge(std::span<const Slab> stored, const ZslabParams& p)
      : stored_(stored),
        p_(p),
        m_(std::clamp(p.rt_layers, 1, kMaxRtLayers)),
        n_(std::clamp(p.layers, 1, kMaxZslabLayers)) {}

  // Adds a slab to the RT layers; a flush when they are full.
  void add(const Slab& s) {
    rt_[rt_count_++] = s;
    if (rt_count_ == m_) flush();
  }

  // Flushes the layers left and writes the merged array to `out`.
  void finish(SlabList& out) {
    if (cur_ < 0 && rt_count_ > 0 && out.capacity() == n_) {
      // One flush in all (the stage's layers fit the RT layers): merge straight into `out`.
      flush_into(out);
      return;
    }
    if (rt_count_ > 0) flush();
    out.clear();
    for (int k = 0; k < cur_count_; ++k) out.push_back(zt_[cur_][k], Overflow::tail);
  }

 private:
  void flush() {
    int dst = cur_ == 0 ? 1 : 0;
    SlabList next(zt_[dst].span(n_));
    flush_into(next);
    cur_ = dst;
    cur_count_ = next.size();
  }

  // Rearranges the RT layers and intermixes them with the current array into `next`.
  void flush_into(SlabList& next) {
    SlabList merged(merged_.span());
    rearrange_layers(rt_.span(rt_count_), merged, p_.mix.interpolation);
    std::span<const Slab> in =
        cur_ < 0 ? stored_ : std::span<const Slab>(zt_[cur_].data(), cur_count_);
    intermix_stage(in, merged.items(), next, p_.mix);
    rt_count_ = 0;
  }

  std::span<const Slab> stored_;
  const ZslabParams& p_;
  int m_, n_;
  SlabScratch<kMaxRtLayers> rt_, merged_;
  SlabScratch<kMaxZslabLayers> zt_[2];
  int rt_count_ = 0, cur_ = -1, cur_count_ = 0;  // cur_ < 0: the stored array is the current one
};

// A polygon stage for one sample: depth peeling keeps each object's first L fragments (sorted by
// t; `peel_by_object`: see peel_limit), they fill the M RT layers, and each time the layers fill
// (and at the end) they are rearranged and intermixed with the array so far. Returns false when
// no fragment touches the sample (the flag buffer's "untouched": `out` is left as it is).
inline bool run_surface_stage(std::span<const Fragment> fragments, const StageThickness& th,
                              std::span<const Slab> stored, SlabList& out, const ZslabParams& p,
                              std::span<const int> peel_by_object = {}) {
  if (fragments.empty()) return false;
  SurfaceStageMerge merge(stored, p);
  int peeled[kMaxRtLayers] = {};
  for (const Fragment& f : fragments) {
    uint32_t o = std::min<uint32_t>(f.object, kMaxRtLayers - 1);
    if (peeled[o] >= peel_limit(peel_by_object, f.object, p.peel_layers))
      continue;  // beyond the L peeling passes of its object
    ++peeled[o];
    merge.add(virtual_slab(f.t, th.of(f.object, f.t), f.color));
  }
  merge.finish(out);
  return true;
}

// A source of at most one slab (an iso-surface hit or a projection).
struct SingleSlabSource {
  Slab slab{};
  bool pending = false;
  bool next(Slab& out) {
    if (!pending) return false;
    pending = false;
    out = slab;
    return true;
  }
};

}  // namespace imx
