#include "volume/brick_min_max.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "core/parallel.hpp"

namespace imx {
namespace {

// The ranges of the bricks of row (by, bz), all of them along x: first voxel-wise over the
// row's 9 x 9 voxel rows (an element-wise min and max of whole rows, which the compiler
// vectorizes), then along x over each brick's span of that. Each voxel is read about 1.27 times
// (rows on a brick boundary belong to two), in order.
template <class T>
void scan_brick_row(const VoxelGrid<T>& g, const BrickGrid& grid, int by, int bz,
                    std::vector<T>& lo, std::vector<T>& hi, glm::vec2* out) {
  constexpr bool kFloat = std::is_floating_point_v<T>;
  constexpr T kHighest =
      kFloat ? std::numeric_limits<T>::infinity() : std::numeric_limits<T>::max();
  constexpr T kLowest = kFloat ? -kHighest : std::numeric_limits<T>::lowest();
  const int nx = g.dims.x;
  std::fill(lo.begin(), lo.end(), kHighest);
  std::fill(hi.begin(), hi.end(), kLowest);
  const glm::ivec3 first = grid.first_voxel({0, by, bz}), last = grid.last_voxel({0, by, bz});
  for (int k = first.z; k <= last.z; ++k)
    for (int j = first.y; j <= last.y; ++j) {
      const T* row = g.data + (static_cast<size_t>(k) * g.dims.y + j) * nx;
      T* l = lo.data();
      T* h = hi.data();
      for (int i = 0; i < nx; ++i) {
        const T v = row[i];
        if constexpr (kFloat) {
          // NaN and inf voxels are no data: left out, as the bounds' own start values (a brick
          // of nothing else holds no data). Told apart by their exponent bits, with no compare
          // of a NaN, so that the loop vectorizes (perf: 10% of a float CT's first image when
          // it did not).
          const bool data = (std::bit_cast<uint32_t>(v) & 0x7f800000u) != 0x7f800000u;
          const T low = data ? v : kHighest, high = data ? v : kLowest;
          l[i] = low < l[i] ? low : l[i];
          h[i] = high > h[i] ? high : h[i];
        } else {
          l[i] = v < l[i] ? v : l[i];
          h[i] = v > h[i] ? v : h[i];
        }
      }
    }
  for (int bx = 0; bx < grid.dims.x; ++bx) {
    T mn = kHighest, mx = kLowest;
    for (int i = grid.first_voxel({bx, 0, 0}).x; i <= grid.last_voxel({bx, 0, 0}).x; ++i) {
      mn = std::min(mn, lo[i]);
      mx = std::max(mx, hi[i]);
    }
    out[bx] = {static_cast<float>(mn), static_cast<float>(mx)};
  }
}

}  // namespace

BrickMinMax::BrickMinMax(const AnyGrid& voxels, glm::ivec3 shape, int threads)
    : grid_(voxels.dims, shape), ranges_(grid_.count()) {
  voxels.visit([&](const auto& g) {
    using T = typename std::decay_t<decltype(g)>::value_type;
    const long rows = static_cast<long>(grid_.dims.y) * grid_.dims.z;
    parallel_for(rows, threads, [&](long begin, long end) {
      std::vector<T> lo(static_cast<size_t>(g.dims.x)), hi(lo.size());
      for (long r = begin; r < end; ++r) {
        const int by = static_cast<int>(r % grid_.dims.y), bz = static_cast<int>(r / grid_.dims.y);
        scan_brick_row(g, grid_, by, bz, lo, hi, &ranges_[grid_.index({0, by, bz})]);
      }
    });
  });
}

}  // namespace imx
