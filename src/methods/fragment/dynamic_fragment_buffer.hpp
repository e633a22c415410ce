// Dynamic fragment buffer (SPEC §6): the resolve side of count / prefix sum / store / sort.
// The rasterizer's per-tile rows are the count pass, the prefix sum and the store pass (in
// arrival order); this is the per-pixel cap and sort. Pure: sorts in place, no allocation.
#pragma once
#include <algorithm>
#include <span>

#include "raster/fragment.hpp"

namespace imx {

inline constexpr int kDefaultFragmentCap = 1024;
// Below this many fragments a pixel is sorted by insertion, above by introsort.
inline constexpr int kInsertionSortBelow = 16;

// Depth order; equal depths keep scene order, so the result does not depend on arrival order.
inline bool fragment_before(const Fragment& a, const Fragment& b) {
  return a.t < b.t || (a.t == b.t && a.object < b.object);
}

// Keeps the first `cap` fragments of a pixel (the store pass has room for no more), sorts them
// by depth and returns them.
inline std::span<Fragment> dfb_sort(std::span<Fragment> arrival, int cap = kDefaultFragmentCap) {
  std::span<Fragment> kept = arrival.first(std::min(arrival.size(), size_t(std::max(cap, 0))));
  if (kept.size() < size_t(kInsertionSortBelow)) {
    for (size_t i = 1; i < kept.size(); ++i) {
      Fragment v = kept[i];
      size_t j = i;
      for (; j > 0 && fragment_before(v, kept[j - 1]); --j) kept[j] = kept[j - 1];
      kept[j] = v;
    }
  } else {
    std::sort(kept.begin(), kept.end(), fragment_before);
  }
  return kept;
}

}  // namespace imx
