// The clip step of one sample ray (SPEC §7, seed 001): from the depth-sorted fragments of the
// clip meshes, the pieces of the ray each clipped volume keeps. Shared by every method.
// Pure, fixed-size, no allocation.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

#include "csg/clip_state.hpp"
#include "csg/mesh_windings.hpp"
#include "raster/fragment.hpp"
#include "volume/kept_span.hpp"
#include "volume/ray_volumes.hpp"

namespace imx {

// The most clip meshes a frame tells apart: one winding each (CsgWindings).
inline constexpr int kMaxClipMeshes = kMaxCsgPrimitives;

// A frame's clip geometry as the kernels read it (ClipPlan owns the arrays).
struct ClipView {
  // Scene::order index -> clip mesh number (its winding), -1 for other objects.
  std::span<const int8_t> slot_of_object;
  // Per volume (Scene::volumes order): the clip meshes that must enclose a sample (digit 1,
  // probing) and those that must not (digit 0, cutting). Neither: the volume is not clipped.
  std::span<const ClipState> rule;

  bool clips(size_t volume) const {
    return volume < rule.size() && (rule[volume].ones | rule[volume].zeros) != 0;
  }
};

// The pieces of the ray that volume `volume`'s clip meshes keep, from the ray's clip-mesh
// fragments sorted by depth. Inside or outside is the non-zero winding of each mesh, started at
// #back - #front faces over the whole row, so a ray that starts inside a cutter (the eye in it,
// its entry clipped by the near plane) is inside from t = 0. Fragments at one depth are passed
// together, so meshes that share a face leave no sliver between them.
inline void clip_volume(std::span<const Fragment> clip_row, const ClipView& view, size_t volume,
                        ClipPieces& out) {
  out.count = 0;
  const ClipState rule = view.rule[volume];
  CsgWindings windings(clip_row, view.slot_of_object);
  bool kept = matches(rule, windings.inside);
  float start = 0.0f;
  for (size_t i = 0; i < clip_row.size();) {
    const float t = clip_row[i].t;
    for (; i < clip_row.size() && clip_row[i].t == t; ++i)
      windings.pass(clip_row[i], view.slot_of_object);
    const bool now = matches(rule, windings.inside);
    if (now == kept) continue;
    if (now)
      start = t;
    else
      out.add(start, t);
    kept = now;
  }
  if (kept) out.add(start, INFINITY);
}

// clip_volume for every clipped volume a ray holds (the first kMaxRayVolumes).
inline void clip_ray(std::span<const Fragment> clip_row, const ClipView& view, RayClip& out) {
  out.clipped = 0;
  const size_t n = std::min<size_t>(view.rule.size(), kMaxRayVolumes);
  for (size_t v = 0; v < n; ++v) {
    if (!view.clips(v)) continue;
    clip_volume(clip_row, view, v, out.volume[v]);
    out.clipped |= VolumeMask{1} << v;
  }
}

}  // namespace imx
