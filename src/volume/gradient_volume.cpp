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
  data_.resize(3 * count + 1);  // the spare entry: see sample()
  // Two passes (largest component, then quantize) instead of a float copy: 6 bytes a voxel at
  // the peak, not 18.
  voxels.visit([&](const auto& g) {
    auto each_slice = [&](auto&& fn) {
      parallel_for(dims_.z, threads, [&](long k0, long k1) {
        for (int k = static_cast<int>(k0); k < k1; ++k)
          for (int j = 0; j < dims_.y; ++j)
            for (int i = 0; i < dims_.x; ++i) {
              size_t n = 3 * ((static_cast<size_t>(k) * dims_.y + j) * dims_.x + i);
              for (int a = 0; a < 3; ++a) fn(n + a, difference(g, {i, j, k}, a), k);
            }
      });
    };
    std::vector<float> largest_per_slice(dims_.z, 0.0f);
    each_slice([&](size_t, float d, int k) {
      if (std::isfinite(d)) largest_per_slice[k] = std::max(largest_per_slice[k], std::abs(d));
    });
    float largest = *std::max_element(largest_per_slice.begin(), largest_per_slice.end());
    scale_ = largest > 0.0f ? largest / 32767.0f : 1.0f;
    const float inv = 1.0f / scale_;
    each_slice([&](size_t n, float d, int) {
      data_[n] = std::isfinite(d) ? static_cast<int16_t>(std::lround(d * inv)) : 0;
    });
  });
}

}  // namespace imx
