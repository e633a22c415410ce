// Thick slabs (SlabProjection): how many samples a slab takes along its normal, and a plane's
// slab value from them (the 2-D reading views' pixels take theirs in frame/slice_view.cpp).
#pragma once
#include <algorithm>
#include <cmath>

#include <glm/vec3.hpp>

#include "intermix/scene.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

// The thick-slab sampling of a volume whose finest voxel pitch is `pitch` mm: `count` samples
// `spacing` mm apart centred on the plane (each the centre of its share of the slab), at most
// kMaxSlabSamples of them (bounded work per pixel). A slab no thicker than the pitch is the plane
// alone.
constexpr int kMaxSlabSamples = 1024;
struct SlabSampling {
  int count = 1;
  double spacing = 0.0;
};
inline SlabSampling slab_sampling(double thickness, double pitch) {
  if (!(thickness > pitch) || !(pitch > 0.0)) return {};
  const double wanted = std::ceil(thickness / pitch - 1e-9);
  const int count = static_cast<int>(std::min<double>(wanted, kMaxSlabSamples));
  return {count, thickness / count};
}

// A plane's slab value at index point `centre` of `volume`: the max, min or mean of the `count`
// samples `step` (index space) apart centred on it that lie in the grid and hold data; false
// when none does, where the plane shows nothing (as a plane's single sample). Pure.
inline bool sample_plane_slab(const PreparedVolume& volume, const glm::vec3& centre,
                              const glm::vec3& step, int count, SlabMode mode, float& value) {
  const glm::vec3 first = centre - step * (0.5f * static_cast<float>(count - 1));
  double sum = 0.0;
  int n = 0;
  for (int k = 0; k < count; ++k) {
    const glm::vec3 p = first + step * static_cast<float>(k);
    if (!volume.grid.inside(p)) continue;
    const float v = volume.grid.sample(p);
    if (!std::isfinite(v)) continue;
    if (n == 0 || (mode == SlabMode::mip && v > value) || (mode == SlabMode::minip && v < value))
      value = v;
    sum += v;
    ++n;
  }
  if (mode == SlabMode::mean && n > 0) value = static_cast<float>(sum / n);
  return n > 0;
}

}  // namespace imx
