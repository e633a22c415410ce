#include "volume/brick_min_max.hpp"

#include <limits>
#include <type_traits>

#include "core/parallel.hpp"

namespace imx {
namespace {

template <class T>
glm::vec2 scan_brick(const VoxelGrid<T>& g, glm::ivec3 lo, glm::ivec3 hi) {
  if constexpr (std::is_floating_point_v<T>) {
    // NaN and inf voxels are no data: left out (a brick of nothing else holds no data).
    constexpr float inf = std::numeric_limits<float>::infinity();
    float mn = inf, mx = -inf;
    for (int k = lo.z; k <= hi.z; ++k)
      for (int j = lo.y; j <= hi.y; ++j) {
        const T* row = g.data + (static_cast<size_t>(k) * g.dims.y + j) * g.dims.x;
        for (int i = lo.x; i <= hi.x; ++i) {
          const float v = row[i];
          const bool data = !no_data(v);
          mn = data && v < mn ? v : mn;
          mx = data && v > mx ? v : mx;
        }
      }
    return {mn, mx};
  } else {
    T mn = g.data[(static_cast<size_t>(lo.z) * g.dims.y + lo.y) * g.dims.x + lo.x];
    T mx = mn;
    for (int k = lo.z; k <= hi.z; ++k)
      for (int j = lo.y; j <= hi.y; ++j) {
        const T* row = g.data + (static_cast<size_t>(k) * g.dims.y + j) * g.dims.x;
        for (int i = lo.x; i <= hi.x; ++i) {
          T v = row[i];
          mn = v < mn ? v : mn;
          mx = v > mx ? v : mx;
        }
      }
    return {static_cast<float>(mn), static_cast<float>(mx)};
  }
}

}  // namespace

BrickMinMax::BrickMinMax(const AnyGrid& voxels, glm::ivec3 shape, int threads)
    : grid_(voxels.dims, shape), ranges_(grid_.count()) {
  voxels.visit([&](const auto& g) {
    parallel_for(static_cast<long>(grid_.count()), threads, [&](long begin, long end) {
      for (long n = begin; n < end; ++n) {
        glm::ivec3 b(static_cast<int>(n % grid_.dims.x),
                     static_cast<int>((n / grid_.dims.x) % grid_.dims.y),
                     static_cast<int>(n / (static_cast<long>(grid_.dims.x) * grid_.dims.y)));
        ranges_[n] = scan_brick(g, grid_.first_voxel(b), grid_.last_voxel(b));
      }
    });
  });
}

}  // namespace imx
