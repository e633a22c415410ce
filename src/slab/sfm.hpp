// SFM: smooth merging of two overlapping fragments into one slab through the intermixing kernel.
#pragma once
#include <algorithm>
#include <span>

#include <glm/vec4.hpp>

#include "slab/intermix_kernel.hpp"
#include "slab/over.hpp"
#include "slab/slab.hpp"
#include "slab/slab_array.hpp"
#include "slab/split.hpp"

namespace imx {

// Splits each fragment at the other's boundaries, mixes the shared part and composites the
// pieces front to back (SPEC §6; the kernel with one slab per sequence). The result covers the
// union of both intervals; for disjoint fragments it is simply the nearer over the farther.
inline Slab sfm(const Slab& a, const Slab& b, const InSlabInterpolation& m = {}) {
  SlabArray<2> pieces;
  IntermixSettings settings{m, 1.0f, Overflow::tail, false};
  intermix(std::span<const Slab>(&a, 1), std::span<const Slab>(&b, 1), pieces, settings);
  glm::vec4 color(0.0f);
  for (const Slab& s : pieces) color = over(color, s.color);
  return Slab::between(std::min(a.front(), b.front()), std::max(a.t_back, b.t_back), color);
}

}  // namespace imx
