// Resolve merge (seed 002 Algorithm 1): depth-sorted fragments to at most M output slabs.
#pragma once
#include <cstddef>
#include <span>

#include "slab/over.hpp"
#include "slab/sfm.hpp"
#include "slab/slab.hpp"
#include "slab/split.hpp"

namespace imx {

// Scans `in` (sorted by back depth) once and writes at most out.size() slabs; returns how many.
// A fragment overlapping the current one merges into it by SFM; otherwise the current one is
// written, except when only the last slot is left: then every later fragment folds into it by
// over, its back depth extended to the fragment's. Without overlaps the front-to-back composite
// of the output equals that of the input.
inline int resolve_merge(std::span<const Slab> in, std::span<Slab> out,
                         const InSlabInterpolation& m = {}) {
  int capacity = int(out.size());
  if (in.empty() || capacity == 0) return 0;
  int n = 0;
  Slab current = in[0];
  for (std::size_t i = 1; i < in.size(); ++i) {
    const Slab& next = in[i];
    if (overlaps(current, next)) {
      current = sfm(current, next, m);
    } else if (n < capacity - 1) {
      out[n++] = current;
      current = next;
    } else {
      current = over(current, next);
    }
  }
  out[n++] = current;
  return n;
}

}  // namespace imx
