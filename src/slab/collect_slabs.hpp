// collect_slabs: a volume's own zSlab array for deferred intermixing (the slab methods' volume
// stage), shared by the per-ray marcher and the packet marcher. Pure.
#pragma once
#include <glm/vec4.hpp>

#include "slab/accumulate.hpp"
#include "slab/over.hpp"
#include "slab/slab.hpp"
#include "slab/slab_array.hpp"

namespace imx {

// A volume's own zSlab array for deferred intermixing: its sample slabs in depth order, folded as
// `overflow` says once `out` is full, until the volume alone reaches the ERT opacity.
// Source: bool next(Slab&) (VolumeMarcher or a single hit).
template <class Source>
inline void collect_slabs(Source& source, SlabList& out, float a_ert, Overflow overflow) {
  out.clear();
  glm::vec4 acc(0.0f);
  Slab s;
  while (!ert_reached(acc.a, a_ert) && source.next(s)) {
    if (s.is_empty()) continue;
    out.push_back(s, overflow);
    acc = over(acc, s.color);
  }
}

}  // namespace imx
