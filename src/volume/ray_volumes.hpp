// RayVolumes: where a ray meets each volume of a frame, the iso-surfaces it crosses and the
// projections (mip, xray) it sees.
// Shared by the per-sample methods; pure, fixed-size, no allocation.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "volume/iso_crossing.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/projection.hpp"

namespace imx {

inline constexpr int kMaxRayVolumes = 16;

// Bit k set: volume k's dvr march may find something on the ray (FrameSetup::volumes_may_show).
using VolumeMask = uint32_t;
inline constexpr VolumeMask kEveryVolume = ~VolumeMask{0};

struct RayVolumes {
  int count = 0;                      // volumes considered (at most kMaxRayVolumes)
  RayInterval span[kMaxRayVolumes];   // each volume's part of the ray
  bool marched[kMaxRayVolumes] = {};  // a visible dvr volume the ray passes through
  VolumeHit hits[kMaxRayVolumes];     // iso hits and projections, sorted by depth
  int hit_count = 0;
  double t_first = INFINITY;  // union of the marched spans
  double t_last = -INFINITY;

  // Intersects the ray with every volume; finds iso crossings and projections on the grid
  // k * step. Dvr volumes outside `may_show` are not marched: they would find nothing.
  RayVolumes(const Ray& ray, std::span<const PreparedVolume> volumes, double step, int bisections,
             std::span<const ShadingLight> lights, VolumeMask may_show = kEveryVolume) {
    count = static_cast<int>(std::min<size_t>(volumes.size(), kMaxRayVolumes));
    for (int k = 0; k < count; ++k) {
      const PreparedVolume& v = volumes[k];
      span[k] = v.intersect(ray);
      if (span[k].empty()) continue;
      VolumeHit h;
      if (v.object->style == VolumeStyle::iso) {
        if (find_iso_crossing(v, ray, span[k].t0, span[k].t1, step, bisections, lights, h))
          hits[hit_count++] = h;
      } else if (v.object->style == VolumeStyle::mip || v.object->style == VolumeStyle::xray) {
        if (project_volume(v, ray, span[k].t0, span[k].t1, step, h)) hits[hit_count++] = h;
      } else if (v.lut.max_opacity() > 0.0f && (may_show >> k & 1u)) {
        marched[k] = true;
        t_first = std::min<double>(t_first, span[k].t0);
        t_last = std::max<double>(t_last, span[k].t1);
      }
    }
    std::sort(hits, hits + hit_count,
              [](const VolumeHit& a, const VolumeHit& b) { return a.t < b.t; });
  }
};

}  // namespace imx
