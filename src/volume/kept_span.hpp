// KeptSpan: the parts of a volume's span that one sample ray samples, where clip geometry keeps
// only some pieces of the ray (SPEC §7). Pure, fixed-size, no allocation.
#pragma once
#include <algorithm>

#include "volume/prepared_volume.hpp"

namespace imx {

// The most pieces one ray keeps of one volume. Fixed so that a kernel needs no allocation; what
// a ray keeps beyond it is merged into its last piece (ClipPieces::add).
inline constexpr int kMaxClipPieces = 8;

// What clip meshes keep of one sample ray: sorted, disjoint, non-empty pieces [t0, t1) from
// t = 0 on, independent of any volume's span (the last may end at infinity).
struct ClipPieces {
  int count = 0;
  RayInterval piece[kMaxClipPieces];

  // Appends [t0, t1), which must not start before the last piece ends. Past the capacity the
  // last piece grows to t1 instead: the gaps beyond kMaxClipPieces are sampled as if kept, so
  // an overly complex cutter shows too much of the volume rather than losing any of it.
  void add(float t0, float t1) {
    if (!(t1 > t0)) return;
    if (count < kMaxClipPieces)
      piece[count++] = {t0, t1};
    else
      piece[count - 1].t1 = t1;
  }
};

// A volume's span seen through clip pieces: piece i is `pieces[i]` clamped to `span`. Without
// pieces the span is kept whole. Trivially copyable; the pieces belong to the caller.
struct KeptSpan {
  RayInterval span;
  const RayInterval* pieces = nullptr;  // sorted, disjoint, each overlapping span; null: span
  int count = 0;                        // pieces kept (0: nothing)

  KeptSpan() = default;
  explicit KeptSpan(RayInterval whole) : span(whole), count(whole.empty() ? 0 : 1) {}

  // The pieces of `clip` that overlap `whole`: those wholly before or behind it are left out,
  // so that every piece read through the view is non-empty.
  KeptSpan(RayInterval whole, const ClipPieces& clip) : span(whole) {
    if (whole.empty()) return;
    int first = 0;
    while (first < clip.count && !(clip.piece[first].t1 > whole.t0)) ++first;
    int last = first;
    while (last < clip.count && clip.piece[last].t0 < whole.t1) ++last;
    pieces = clip.piece + first;
    count = last - first;
  }

  int size() const { return count; }
  bool empty() const { return count == 0; }
  RayInterval operator[](int i) const {
    if (!pieces) return span;
    return {std::max(pieces[i].t0, span.t0), std::min(pieces[i].t1, span.t1)};
  }
  // The kept extent: from the first piece's start to the last one's end (not empty()).
  float front() const { return (*this)[0].t0; }
  float back() const { return (*this)[count - 1].t1; }
  // Whether depth t lies in a kept piece.
  bool contains(double t) const {
    for (int i = 0; i < count; ++i) {
      const RayInterval p = (*this)[i];
      if (t < p.t0) return false;
      if (t < p.t1) return true;
    }
    return false;
  }
};

}  // namespace imx
