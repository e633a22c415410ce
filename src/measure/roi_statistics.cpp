#include "measure/roi_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include <glm/glm.hpp>

namespace imx {
namespace {

// Calls visit(index) for each voxel inside the region, by the rule of roi_statistics.hpp. The two
// index axes least along the normal are walked over the region's index box; along the third the
// voxels the plane passes through are solved for, so the work is the voxels in the slab.
template <class Visit>
void for_each_inside(const VolumeObject& volume, const PlanarRegion& region, Visit&& visit) {
  const glm::dmat4& m = volume.index_to_world;
  const glm::dvec3 n = region.normal();
  const glm::dvec3 step[3] = {glm::dvec3(m[0]), glm::dvec3(m[1]), glm::dvec3(m[2])};
  const double along[3] = {glm::dot(n, step[0]), glm::dot(n, step[1]), glm::dot(n, step[2])};
  // Half the voxel box's extent along the normal: its support in that direction.
  const double h = 0.5 * (std::abs(along[0]) + std::abs(along[1]) + std::abs(along[2]));
  const glm::ivec3 dims = volume.data->dims;
  if (dims.x <= 0 || dims.y <= 0 || dims.z <= 0 || !(h > 0.0)) return;

  // The region's box, thickened by h both ways, in index space.
  const glm::dmat4 to_index = glm::inverse(m);
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 w = region.origin() + ((c & 1) ? region.hi().x : region.lo().x) * region.u() +
                         ((c & 2) ? region.hi().y : region.lo().y) * region.v() +
                         ((c & 4) ? h : -h) * n;
    const glm::dvec3 p = glm::dvec3(to_index * glm::dvec4(w, 1.0));
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  glm::ivec3 first, last;
  for (int a = 0; a < 3; ++a) {
    // Index coordinates beyond an int are outside any grid: clamp in doubles first.
    first[a] = static_cast<int>(std::clamp(std::floor(lo[a]), 0.0, double(dims[a] - 1)));
    last[a] = static_cast<int>(std::clamp(std::ceil(hi[a]), 0.0, double(dims[a] - 1)));
    if (hi[a] < 0.0 || lo[a] > dims[a] - 1) return;
  }
  // Solve along the axis most along the normal.
  int s = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(along[a]) > std::abs(along[s])) s = a;
  const int p = (s + 1) % 3, q = (s + 2) % 3;
  const glm::dvec3 origin = glm::dvec3(m[3]);
  glm::ivec3 idx;
  for (idx[q] = first[q]; idx[q] <= last[q]; ++idx[q])
    for (idx[p] = first[p]; idx[p] <= last[p]; ++idx[p]) {
      // Signed distance of the voxel centre at idx[s] = 0, and its change per step along s.
      glm::ivec3 base = idx;
      base[s] = 0;
      const glm::dvec3 w0 =
          origin + double(base.x) * step[0] + double(base.y) * step[1] + double(base.z) * step[2];
      const double d0 = glm::dot(n, w0 - region.origin());
      // -h <= d0 + k * along[s] < h.
      double k_lo = (-h - d0) / along[s], k_hi = (h - d0) / along[s];
      if (k_lo > k_hi) std::swap(k_lo, k_hi);
      // Widened by a hair: the exact test below decides; clamped in doubles before the cast.
      const double top = double(dims[s]);
      const int k0 = std::max(first[s], int(std::clamp(std::ceil(k_lo - 1e-9), -1.0, top)));
      const int k1 = std::min(last[s], int(std::clamp(std::floor(k_hi + 1e-9), -1.0, top)));
      for (idx[s] = k0; idx[s] <= k1; ++idx[s]) {
        const glm::dvec3 w = w0 + double(idx[s]) * step[s];
        const double d = glm::dot(n, w - region.origin());
        if (d < -h || d >= h) continue;  // the exact rule; the range above only narrows the walk
        if (region.contains(region.in_plane(w))) visit(idx);
      }
    }
}

}  // namespace

std::vector<glm::ivec3> roi_voxels(const VolumeObject& volume, const PlanarRegion& region) {
  std::vector<glm::ivec3> out;
  for_each_inside(volume, region, [&](const glm::ivec3& i) { out.push_back(i); });
  std::sort(out.begin(), out.end(), [](const glm::ivec3& a, const glm::ivec3& b) {
    return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x);
  });
  return out;
}

RoiStatistics roi_statistics(const VolumeObject& volume, const PlanarRegion& region) {
  RoiStatistics r;
  // Welford's running mean and sum of squared deviations: stable for large offsets (HU + 1024).
  double mean = 0.0, m2 = 0.0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  const VolumeData& data = *volume.data;
  for_each_inside(volume, region, [&](const glm::ivec3& i) {
    const double value = data.value_at(i.x, i.y, i.z);
    if (!std::isfinite(value)) {
      ++r.non_finite;
      return;
    }
    ++r.voxels;
    const double delta = value - mean;
    mean += delta / static_cast<double>(r.voxels);
    m2 += delta * (value - mean);
    lo = std::min(lo, value);
    hi = std::max(hi, value);
  });
  if (r.voxels == 0) {
    r.mean = r.sd = r.min = r.max = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  r.mean = mean;
  r.sd = std::sqrt(std::max(0.0, m2 / static_cast<double>(r.voxels)));
  r.min = lo;
  r.max = hi;
  return r;
}

}  // namespace imx
