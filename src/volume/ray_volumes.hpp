// RayVolumes: where a ray meets each volume of a frame (its span, and the pieces of it clip
// geometry keeps), the iso-surfaces it crosses and the projections (mip, minip, xray) it sees.
// Shared by the per-sample methods; pure, fixed-size, no allocation.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "volume/iso_crossing.hpp"
#include "volume/kept_span.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/projection.hpp"

namespace imx {

inline constexpr int kMaxRayVolumes = 16;

// Bit k set: volume k's dvr march may find something on the ray (FrameSetup::volumes_may_show).
using VolumeMask = uint32_t;
inline constexpr VolumeMask kEveryVolume = ~VolumeMask{0};

// The pieces of one sample ray that clip geometry keeps of each clipped volume (SPEC §7), found
// once per ray by the clip step (frame/clip_intervals.hpp) before the method's kernel runs.
struct RayClip {
  VolumeMask clipped = 0;  // bit k: volume k has clip meshes, and volume[k] is what they keep
  ClipPieces volume[kMaxRayVolumes];
};

// What the frame knows of a sample's volumes before its kernel runs: which may show in its pixel
// (FrameSetup::volumes_may_show) and, in a scene with clip geometry, what the ray keeps of them.
struct VolumeFilter {
  VolumeMask may_show = kEveryVolume;
  const RayClip* clip = nullptr;  // null: no volume is clipped

  VolumeFilter(VolumeMask mask = kEveryVolume, const RayClip* kept = nullptr)
      : may_show(mask), clip(kept) {}
};

struct RayVolumes {
  int count = 0;                      // volumes considered (at most kMaxRayVolumes)
  RayInterval span[kMaxRayVolumes];   // each volume's part of the ray
  bool marched[kMaxRayVolumes] = {};  // a visible dvr volume the ray keeps some of
  VolumeHit hits[kMaxRayVolumes];     // iso hits and projections, sorted by depth
  int hit_count = 0;

  // Intersects the ray with every volume and, for clipped ones, keeps only the pieces of the
  // filter's RayClip; finds iso crossings and projections on the grid k * step within what is
  // kept. Dvr volumes outside `may_show` are not marched: they would find nothing.
  RayVolumes(const Ray& ray, std::span<const PreparedVolume> volumes, double step, int bisections,
             std::span<const ShadingLight> lights, VolumeFilter filter = {})
      : clip_(filter.clip) {
    count = static_cast<int>(std::min<size_t>(volumes.size(), kMaxRayVolumes));
    for (int k = 0; k < count; ++k) {
      const PreparedVolume& v = volumes[k];
      span[k] = v.intersect(ray);
      if (span[k].empty()) continue;
      const KeptSpan what = kept(k);
      if (what.empty()) continue;
      VolumeHit h;
      if (v.object->style == VolumeStyle::iso) {
        if (find_iso_crossing(v, ray, what, step, bisections, lights, h)) hits[hit_count++] = h;
      } else if (v.object->style != VolumeStyle::dvr) {  // mip, minip, xray
        if (project_volume(v, ray, what, step, h)) hits[hit_count++] = h;
      } else if (v.lut.max_opacity() > 0.0f && (filter.may_show >> k & 1u)) {
        marched[k] = true;
      }
    }
    std::sort(hits, hits + hit_count,
              [](const VolumeHit& a, const VolumeHit& b) { return a.t < b.t; });
  }

  // What the ray samples of volume k: its span, or the pieces of it that clip geometry keeps.
  KeptSpan kept(int k) const {
    if (clip_ && (clip_->clipped >> k & 1u)) return KeptSpan(span[k], clip_->volume[k]);
    return KeptSpan(span[k]);
  }

 private:
  const RayClip* clip_ = nullptr;
};

}  // namespace imx
