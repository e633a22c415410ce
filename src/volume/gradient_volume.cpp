#include "volume/gradient_volume.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "core/parallel.hpp"

namespace imx {

namespace {

// The central difference along one axis at voxel p of a volume with no data (NaN or inf voxels)
// where the plain one (row_differences) is not finite: taken again one-sided beside the no data
// (a neighbour of no data is replaced by the centre, and a voxel of no data has 0).
template <class Grid>
float careful_difference(const Grid& g, glm::ivec3 p, int axis) {
  glm::ivec3 lo = p, hi = p;
  lo[axis] = std::max(p[axis] - 1, 0);
  hi[axis] = std::min(p[axis] + 1, g.dims[axis] - 1);
  if (no_data(g.at(p.x, p.y, p.z))) return 0.0f;
  if (no_data(g.at(hi.x, hi.y, hi.z))) hi = p;
  if (no_data(g.at(lo.x, lo.y, lo.z))) lo = p;
  const int span = hi[axis] - lo[axis];
  if (span == 0) return 0.0f;
  return (g.at(hi.x, hi.y, hi.z) - g.at(lo.x, lo.y, lo.z)) / static_cast<float>(span);
}

// The bits of |x| where x is finite, else 0: non-negative floats order as their bits, so the
// largest of them is an integer maximum, which vectorizes where a float one does not.
inline uint32_t finite_magnitude_bits(float x) {
  const uint32_t bits = std::bit_cast<uint32_t>(x) & 0x7fffffffu;
  return bits < 0x7f800000u ? bits : 0u;
}

// std::lround(x) for |x| below 2^15, 0 where x is not finite, with no branch and no compare of a
// non-finite value, so that GCC vectorizes it: the build quantizes three values a voxel, and
// libm's lroundf, one call each, took 13% of a float CT's first image (perf, the tilted GE CT).
inline int16_t quantized(float x) {
  const float y = finite_magnitude_bits(x) == 0u ? 0.0f : x;
  const int whole = static_cast<int>(y);             // toward zero
  const float rest = y - static_cast<float>(whole);  // exact
  return static_cast<int16_t>(whole + (rest >= 0.5f) - (rest <= -0.5f));
}

// out[3 i + a] = quantized(d_a[i] * inv) for the n voxels of a row, interleaved as the int16
// layout stores them: one loop without branches, which vectorizes.
void quantize_row(const float* dx, const float* dy, const float* dz, float inv, int16_t* out,
                  int n) {
  for (int i = 0; i < n; ++i) {
    out[3 * i] = quantized(dx[i] * inv);
    out[3 * i + 1] = quantized(dy[i] * inv);
    out[3 * i + 2] = quantized(dz[i] * inv);
  }
}

// The central differences along x, y and z of row (j, k), one-sided at the borders, a row at a
// time so that the loops vectorize (a span of 2 halves exactly); Careful (a volume with no data):
// the non-finite ones are taken again by careful_difference.
template <bool Careful, class Grid>
void row_differences(const Grid& g, int j, int k, float* dx, float* dy, float* dz) {
  const int nx = g.dims.x;
  auto row = [&](int jj, int kk) {
    return g.data + (static_cast<size_t>(kk) * g.dims.y + jj) * nx;
  };
  const auto* r = row(j, k);
  auto at = [](const auto* q, int i) { return static_cast<float>(q[i]); };
  if (nx == 1) {
    dx[0] = 0.0f;
  } else {
    dx[0] = at(r, 1) - at(r, 0);
    for (int i = 1; i + 1 < nx; ++i) dx[i] = (at(r, i + 1) - at(r, i - 1)) / 2.0f;
    dx[nx - 1] = at(r, nx - 1) - at(r, nx - 2);
  }
  // Along y and z every voxel of the row has the same neighbours' rows and span.
  auto across = [&](const auto* lo, const auto* hi, int span, float* d) {
    if (span == 0) {
      std::fill(d, d + nx, 0.0f);
      return;
    }
    const float s = static_cast<float>(span);
    for (int i = 0; i < nx; ++i) d[i] = (at(hi, i) - at(lo, i)) / s;
  };
  const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, g.dims.y - 1);
  const int k0 = std::max(k - 1, 0), k1 = std::min(k + 1, g.dims.z - 1);
  across(row(j0, k), row(j1, k), j1 - j0, dy);
  across(row(j, k0), row(j, k1), k1 - k0, dz);
  if constexpr (Careful) {
    float* d[3] = {dx, dy, dz};
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < nx; ++i)
        if (!std::isfinite(d[a][i])) d[a][i] = careful_difference(g, {i, j, k}, a);
  }
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
    // fn(first voxel n of the row, slice k, its differences along x, y and z) for every row.
    auto each_row = [&](auto careful, auto&& fn) {
      parallel_for(dims_.z, threads, [&](long k0, long k1) {
        std::vector<float> d(3 * static_cast<size_t>(dims_.x));
        float *dx = d.data(), *dy = dx + dims_.x, *dz = dy + dims_.x;
        for (int k = static_cast<int>(k0); k < k1; ++k)
          for (int j = 0; j < dims_.y; ++j) {
            row_differences<decltype(careful)::value>(g, j, k, dx, dy, dz);
            fn((static_cast<size_t>(k) * dims_.y + j) * dims_.x, k, dx, dy, dz);
          }
      });
    };
    // NaN or inf voxels (no data) make differences non-finite: only then are they taken
    // carefully, one-sided beside the no data, so other volumes never pay for the test.
    bool careful = false;
    if constexpr (std::is_floating_point_v<T>)
      careful = std::count_if(g.data, g.data + count, [](float v) { return no_data(v); }) > 0;
    const int nx = dims_.x;
    std::vector<uint32_t> largest_per_slice(dims_.z, 0u);  // finite_magnitude_bits
    auto find_largest = [&](size_t, int k, const float* dx, const float* dy, const float* dz) {
      uint32_t m = largest_per_slice[k];
      for (const float* d : {dx, dy, dz})
        for (int i = 0; i < nx; ++i) m = std::max(m, finite_magnitude_bits(d[i]));
      largest_per_slice[k] = m;
    };
    if (careful)
      each_row(std::true_type{}, find_largest);
    else
      each_row(std::false_type{}, find_largest);
    const float largest =
        std::bit_cast<float>(*std::max_element(largest_per_slice.begin(), largest_per_slice.end()));
    // Integer voxels make every 2 x difference an integer: exact in 10 bits up to 511.
    if (std::is_integral_v<T> && 2.0f * largest <= 511.0f) {
      scale_ = 0.5f;
      words_.assign(count, 0u);
      each_row(std::false_type{},
               [&](size_t n, int, const float* dx, const float* dy, const float* dz) {
                 auto code = [](float d) {
                   return static_cast<uint32_t>(static_cast<int>(2.0f * d)) & 0x3ffu;  // an integer
                 };
                 for (int i = 0; i < nx; ++i)
                   words_[n + i] = code(dx[i]) | code(dy[i]) << 10 | code(dz[i]) << 20;
               });
      return;
    }
    scale_ = largest > 0.0f ? largest / 32767.0f : 1.0f;
    const float inv = 1.0f / scale_;
    data_.resize(3 * count + 2);  // the spare entries: see data()
    auto store = [&](size_t n, int, const float* dx, const float* dy, const float* dz) {
      quantize_row(dx, dy, dz, inv, &data_[3 * n], nx);
    };
    if (careful)
      each_row(std::true_type{}, store);
    else
      each_row(std::false_type{}, store);
  });
}

}  // namespace imx
