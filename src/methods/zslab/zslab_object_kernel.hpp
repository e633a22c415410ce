// Object-level zSlab kernels for one sample (SPEC §4, reuse): a surface stage split into the
// object's own peeled virtual slabs and their merge into a stored array. Together they do exactly
// what run_surface_stage does, so a kept own array can be merged again without rasterizing.
// Pure: fixed-size arrays on the stack, no allocation, no exceptions.
#pragma once
#include <algorithm>
#include <cstdint>
#include <span>

#include "methods/zslab/zslab_kernel.hpp"

namespace imx {

// The most own slabs one surface stage may keep per sample (objects x L); larger stages are run
// whole every frame instead.
inline constexpr int kMaxOwnSurfaceSlabs = 64;

// The peeled virtual slabs of a surface stage in fragment (depth) order: each object's first L
// fragments (or its peel_limit), as run_surface_stage fills its RT layers. Returns how many were
// written to `own`; a stage whose fragments do not fit `own` loses the rest (callers size it as
// the sum of the objects' limits).
inline int peel_surface_slabs(std::span<const Fragment> fragments, const StageThickness& th,
                              int peel_layers, std::span<Slab> own,
                              std::span<const int> peel_by_object = {}) {
  int peeled[kMaxRtLayers] = {};
  int count = 0;
  for (const Fragment& f : fragments) {
    uint32_t o = std::min<uint32_t>(f.object, kMaxRtLayers - 1);
    if (peeled[o] >= peel_limit(peel_by_object, f.object, peel_layers))
      continue;  // beyond the L peeling passes of its object
    if (count == static_cast<int>(own.size())) break;
    ++peeled[o];
    own[static_cast<size_t>(count++)] = virtual_slab(f.t, th.of(f.object, f.t), f.color);
  }
  return count;
}

// Merges peeled slabs (peel_surface_slabs) into `stored`, M at a time through the rearrangement
// and the kernel, as run_surface_stage does. False (and `out` untouched) when there are none.
inline bool merge_surface_slabs(std::span<const Slab> own, std::span<const Slab> stored,
                                SlabList& out, const ZslabParams& p) {
  if (own.empty()) return false;
  if (own.size() == 1) {  // one layer rearranges to itself (or to nothing when it is empty)
    out.clear();
    intermix(stored, own[0].is_empty() ? std::span<const Slab>() : own, out, p.mix);
    return true;
  }
  SurfaceStageMerge merge(stored, p);
  for (const Slab& s : own) merge.add(s);
  merge.finish(out);
  return true;
}

}  // namespace imx
