#include "volume/gradient_volume.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "core/parallel.hpp"

namespace imx {

namespace {

// Central difference along one axis at voxel i, one-sided at the borders. Careful (a volume with
// no data): a non-finite difference is taken again one-sided beside the no data (NaN or inf voxels:
// a neighbour of no data is replaced by the centre, and a voxel of no data then has 0).
template <bool Careful, class Grid>
float difference(const Grid& g, glm::ivec3 p, int axis) {
  glm::ivec3 lo = p, hi = p;
  lo[axis] = std::max(p[axis] - 1, 0);
  hi[axis] = std::min(p[axis] + 1, g.dims[axis] - 1);
  int span = hi[axis] - lo[axis];
  if (span == 0) return 0.0f;
  const float d = (g.at(hi.x, hi.y, hi.z) - g.at(lo.x, lo.y, lo.z)) / static_cast<float>(span);
  if constexpr (Careful && std::is_floating_point_v<typename Grid::value_type>) {
    if (!std::isfinite(d)) {
      if (no_data(g.at(p.x, p.y, p.z))) return 0.0f;
      if (no_data(g.at(hi.x, hi.y, hi.z))) hi = p;
      if (no_data(g.at(lo.x, lo.y, lo.z))) lo = p;
      span = hi[axis] - lo[axis];
      if (span == 0) return 0.0f;
      return (g.at(hi.x, hi.y, hi.z) - g.at(lo.x, lo.y, lo.z)) / static_cast<float>(span);
    }
  }
  return d;
}

}  // namespace

uint64_t GradientVolume::bytes_at_most(const VolumeData& data) {
  return static_cast<uint64_t>(data.voxel_count()) * (data.type() == VoxelType::u8 ? 4 : 6);
}

GradientVolume::GradientVolume(const AnyGrid& voxels, int threads) : dims_(voxels.dims) {
  const size_t count = static_cast<size_t>(dims_.x) * dims_.y * dims_.z;
  // Two passes (largest component, then quantize) instead of a float copy: the stored size at
  // the peak, not 18 bytes a voxel.
  voxels.visit([&](const auto& g) {
    using T = std::remove_cvref_t<decltype(*g.data)>;
    auto each_slice = [&](auto careful, auto&& fn) {
      parallel_for(dims_.z, threads, [&](long k0, long k1) {
        for (int k = static_cast<int>(k0); k < k1; ++k)
          for (int j = 0; j < dims_.y; ++j)
            for (int i = 0; i < dims_.x; ++i) {
              size_t n = (static_cast<size_t>(k) * dims_.y + j) * dims_.x + i;
              for (int a = 0; a < 3; ++a)
                fn(n, a, difference<decltype(careful)::value>(g, {i, j, k}, a), k);
            }
      });
    };
    // NaN or inf voxels (no data) make differences non-finite: only then are they taken
    // carefully, one-sided beside the no data, so other volumes never pay for the test.
    bool careful = false;
    if constexpr (std::is_floating_point_v<T>)
      careful = std::count_if(g.data, g.data + count, [](float v) { return no_data(v); }) > 0;
    std::vector<float> largest_per_slice(dims_.z, 0.0f);
    auto find_largest = [&](size_t, int, float d, int k) {
      if (std::isfinite(d)) largest_per_slice[k] = std::max(largest_per_slice[k], std::abs(d));
    };
    if (careful)
      each_slice(std::true_type{}, find_largest);
    else
      each_slice(std::false_type{}, find_largest);
    float largest = *std::max_element(largest_per_slice.begin(), largest_per_slice.end());
    // Integer voxels make every 2 x difference an integer: exact in 10 bits up to 511.
    if (std::is_integral_v<T> && 2.0f * largest <= 511.0f) {
      scale_ = 0.5f;
      words_.assign(count, 0u);
      each_slice(std::false_type{}, [&](size_t n, int a, float d, int) {
        uint32_t code = static_cast<uint32_t>(static_cast<int>(std::lround(2.0f * d))) & 0x3ffu;
        words_[n] |= code << (10 * a);  // one thread writes all three fields of a voxel
      });
      return;
    }
    scale_ = largest > 0.0f ? largest / 32767.0f : 1.0f;
    const float inv = 1.0f / scale_;
    data_.resize(3 * count + 2);  // the spare entries: see data()
    auto store = [&](size_t n, int a, float d, int) {
      data_[3 * n + a] = std::isfinite(d) ? static_cast<int16_t>(std::lround(d * inv)) : 0;
    };
    if (careful)
      each_slice(std::true_type{}, store);
    else
      each_slice(std::false_type{}, store);
  });
}

}  // namespace imx
