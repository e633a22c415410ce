// Thick slabs (SlabProjection): how many samples a slab takes along its normal, and a plane's
// slab value from them (the 2-D reading views' pixels take theirs in frame/slice_view.cpp).
#pragma once
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "intermix/scene.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

// The thick-slab sampling of a volume whose voxel pitch along the slab's normal is `pitch` mm:
// `count` samples `spacing` mm apart centred on the plane (each the centre of its share of the
// slab), at most kMaxSlabSamples of them (bounded work per pixel). A slab no thicker than the pitch
// is the plane alone.
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

// The voxel pitch along unit world direction `n`: the mm of one voxel step (index space) along
// it, the finest pitch for a normal along a grid axis, at most the coarsest for any other.
inline double pitch_along(const PreparedVolume& volume, const glm::dvec3& n) {
  const glm::vec3 d = volume.to_index(glm::vec3(n)) - volume.to_index(glm::vec3(0.0f));
  const double voxels_per_mm = glm::length(glm::dvec3(d));
  return voxels_per_mm > 0.0 ? 1.0 / voxels_per_mm : 0.0;
}

// The max, min or mean of the `count` samples of `grid` `step` (index space) apart centred on
// index point `centre`, of those inside [lo, hi] (each is tested only when the slab's ends are
// not both inside, as the box is convex) and, with `skip_no_data`, finite; false when none is.
// Pure, no allocation: the innermost loop of every thick-slab pixel, the voxel type chosen once.
inline bool slab_along(const AnyGrid& grid, const glm::vec3& centre, const glm::vec3& step,
                       int count, SlabMode mode, const glm::vec3& lo, const glm::vec3& hi,
                       bool skip_no_data, float& value) {
  const glm::vec3 first = centre - step * (0.5f * static_cast<float>(count - 1));
  const glm::vec3 last = first + step * static_cast<float>(count - 1);
  const auto in = [&](const glm::vec3& q) {
    return q.x >= lo.x && q.y >= lo.y && q.z >= lo.z && q.x <= hi.x && q.y <= hi.y && q.z <= hi.z;
  };
  const bool check = !(in(first) && in(last));
  return grid.visit([&](const auto& g) {
    float best = 0.0f;
    double sum = 0.0;
    int n = 0;
    for (int k = 0; k < count; ++k) {
      const glm::vec3 q = first + step * static_cast<float>(k);
      if (check && !in(q)) continue;
      const float v = g.sample(q);
      if (skip_no_data && !std::isfinite(v)) continue;
      if (n++ == 0 || (mode == SlabMode::mip ? v > best : mode == SlabMode::minip && v < best))
        best = v;
      if (mode == SlabMode::mean) sum += v;
    }
    if (n > 0) value = mode == SlabMode::mean ? static_cast<float>(sum / n) : best;
    return n > 0;
  });
}

// A plane's slab value at index point `centre` of `volume`: slab_along within the grid's hull
// [0, dims - 1], as a plane's single sample (sample_plane_volume); false where the plane shows
// nothing.
inline bool sample_plane_slab(const PreparedVolume& volume, const glm::vec3& centre,
                              const glm::vec3& step, int count, SlabMode mode, float& value) {
  return slab_along(volume.grid, centre, step, count, mode, glm::vec3(0.0f),
                    glm::vec3(volume.grid.dims - 1), volume.has_no_data, value);
}

}  // namespace imx
