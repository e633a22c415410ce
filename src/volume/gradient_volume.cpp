#include "volume/gradient_volume.hpp"

#include <algorithm>
#include <cmath>

#include "core/parallel.hpp"

namespace imx {

namespace {

// Central difference along one axis at voxel i, one-sided at the borders.
template <class Grid>
float difference(const Grid& g, glm::ivec3 p, int axis) {
  glm::ivec3 lo = p, hi = p;
  lo[axis] = std::max(p[axis] - 1, 0);
  hi[axis] = std::min(p[axis] + 1, g.dims[axis] - 1);
  int span = hi[axis] - lo[axis];
  if (span == 0) return 0.0f;
  return (g.at(hi.x, hi.y, hi.z) - g.at(lo.x, lo.y, lo.z)) / static_cast<float>(span);
}

}  // namespace

GradientVolume::GradientVolume(const AnyGrid& voxels, int threads) : dims_(voxels.dims) {
  const size_t count = static_cast<size_t>(dims_.x) * dims_.y * dims_.z;
  std::vector<float> full(3 * count);
  voxels.visit([&](const auto& g) {
    parallel_for(dims_.z, threads, [&](long k0, long k1) {
      for (int k = static_cast<int>(k0); k < k1; ++k)
        for (int j = 0; j < dims_.y; ++j)
          for (int i = 0; i < dims_.x; ++i) {
            size_t n = 3 * ((static_cast<size_t>(k) * dims_.y + j) * dims_.x + i);
            for (int a = 0; a < 3; ++a) full[n + a] = difference(g, {i, j, k}, a);
          }
    });
  });
  float largest = 0.0f;
  for (float v : full)
    if (std::isfinite(v)) largest = std::max(largest, std::abs(v));
  scale_ = largest > 0.0f ? largest / 32767.0f : 1.0f;
  data_.resize(full.size());
  const float inv = 1.0f / scale_;
  for (size_t n = 0; n < full.size(); ++n)
    data_[n] = std::isfinite(full[n]) ? static_cast<int16_t>(std::lround(full[n] * inv)) : 0;
}

}  // namespace imx
