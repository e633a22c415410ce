#include "figure/figure_extent.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <tbb/parallel_for.h>

#include "core/math.hpp"
#include "volume/value_sample.hpp"

namespace imx {
namespace {

constexpr double kMaxScanned = 16.0 * 1024 * 1024;

// Every s-th voxel along each axis, s chosen for at most kMaxScanned voxels.
int scan_stride(const glm::ivec3& dims) {
  const double voxels = static_cast<double>(dims.x) * dims.y * dims.z;
  return std::max(1, static_cast<int>(std::ceil(std::cbrt(voxels / kMaxScanned))));
}

WorldBox cell_box(const VolumeObject& volume, glm::dvec3 index_lo, glm::dvec3 index_hi) {
  WorldBox box{glm::dvec3(1e300), glm::dvec3(-1e300)};
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 index((c & 1) ? index_hi.x : index_lo.x, (c & 2) ? index_hi.y : index_lo.y,
                           (c & 4) ? index_hi.z : index_lo.z);
    const glm::dvec3 w = transform_point(volume.index_to_world, index);
    box.lo = glm::min(box.lo, w);
    box.hi = glm::max(box.hi, w);
  }
  return box;
}

}  // namespace

std::optional<WorldBox> voxel_box(const VolumeObject& volume,
                                  const std::function<bool(double)>& keep) {
  const VolumeData& data = *volume.data;
  const glm::ivec3 dims = data.dims;
  const int s = scan_stride(dims);
  const int planes = (dims.z + s - 1) / s;
  // Per scanned k plane: the index box of its kept voxels (lo > hi when none).
  std::vector<std::array<glm::ivec3, 2>> found(static_cast<size_t>(planes),
                                               {glm::ivec3(INT32_MAX), glm::ivec3(INT32_MIN)});
  tbb::parallel_for(0, planes, [&](int p) {
    const int k = p * s;
    auto& [lo, hi] = found[static_cast<size_t>(p)];
    for (int j = 0; j < dims.y; j += s)
      for (int i = 0; i < dims.x; i += s) {
        const double v = data.value_at(i, j, k);
        if (!std::isfinite(v) || !keep(v)) continue;
        lo = glm::min(lo, glm::ivec3(i, j, k));
        hi = glm::max(hi, glm::ivec3(i, j, k));
      }
  });
  glm::ivec3 lo(INT32_MAX), hi(INT32_MIN);
  for (const auto& [a, b] : found) {
    lo = glm::min(lo, a);
    hi = glm::max(hi, b);
  }
  if (lo.x > hi.x) return std::nullopt;
  // The kept voxels' cells, widened by the stride (an unscanned neighbour may be kept too).
  const glm::dvec3 margin(0.5 + (s - 1));
  return cell_box(volume, glm::max(glm::dvec3(lo) - margin, glm::dvec3(-0.5)),
                  glm::min(glm::dvec3(hi) + margin, glm::dvec3(dims) - 0.5));
}

std::optional<double> background_level(const VolumeObject& anatomy) {
  constexpr std::array<double, 2> kRobust = {0.02, 0.98};
  const std::vector<double> q = value_percentiles(*anatomy.data, kRobust);
  if (q.size() == 2 && q[1] > q[0]) return q[0] + 0.1 * (q[1] - q[0]);
  return std::nullopt;
}

WorldBox grid_box(const VolumeObject& volume) {
  return cell_box(volume, glm::dvec3(-0.5), glm::dvec3(volume.data->dims) - 0.5);
}

WorldBox anatomy_box(const VolumeObject& anatomy) {
  if (const std::optional<double> background = background_level(anatomy))
    if (auto box = voxel_box(anatomy, [&](double v) { return v > *background; })) return *box;
  return grid_box(anatomy);
}

glm::dvec3 peak_point(const VolumeObject& volume) {
  const VolumeData& data = *volume.data;
  const glm::ivec3 dims = data.dims;
  struct Peak {
    double magnitude = -1.0;
    glm::ivec3 index{0};
  };
  std::vector<Peak> per_plane(static_cast<size_t>(dims.z));
  tbb::parallel_for(0, dims.z, [&](int k) {
    Peak& peak = per_plane[static_cast<size_t>(k)];
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i) {
        const double m = std::abs(data.value_at(i, j, k));
        if (std::isfinite(m) && m > peak.magnitude) peak = {m, {i, j, k}};
      }
  });
  Peak best;
  for (const Peak& p : per_plane)
    if (p.magnitude > best.magnitude) best = p;
  const glm::dvec3 index =
      best.magnitude >= 0.0 ? glm::dvec3(best.index) : 0.5 * glm::dvec3(dims - 1);
  return transform_point(volume.index_to_world, index);
}

}  // namespace imx
