#include <algorithm>
#include <vector>

#include "core/parallel.hpp"
#include "intermix/metrics.hpp"
#include "metrics/pixel_errors.hpp"

namespace imx {

namespace {

constexpr int kWindow = 8;
constexpr int kStride = 4;
constexpr double kC1 = 0.01 * 0.01;  // (K1 L)^2 with L = 1
constexpr double kC2 = 0.03 * 0.03;  // (K2 L)^2

// Window origins along one axis; a last window flush with the edge covers what the stride misses.
std::vector<int> window_starts(int size) {
  if (size <= kWindow) return {0};
  std::vector<int> starts;
  for (int s = 0; s + kWindow <= size; s += kStride) starts.push_back(s);
  if (starts.back() + kWindow < size) starts.push_back(size - kWindow);
  return starts;
}

// SSIM of one w x h window; every product is written symmetrically so ssim(a,b) == ssim(b,a).
double window_ssim(const float* a, const float* b, int row_stride, int w, int h) {
  double n = double(w) * h, sum_a = 0.0, sum_b = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      sum_a += a[y * row_stride + x];
      sum_b += b[y * row_stride + x];
    }
  double mean_a = sum_a / n, mean_b = sum_b / n;
  // Centred sums rather than E[x^2] - mean^2, which cancels badly on flat windows.
  double var_a = 0.0, var_b = 0.0, cov = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double da = a[y * row_stride + x] - mean_a, db = b[y * row_stride + x] - mean_b;
      var_a += da * da;
      var_b += db * db;
      cov += da * db;
    }
  var_a /= n;
  var_b /= n;
  cov /= n;
  return ((2.0 * (mean_a * mean_b) + kC1) * (2.0 * cov + kC2)) /
         ((mean_a * mean_a + mean_b * mean_b + kC1) * (var_a + var_b + kC2));
}

}  // namespace

double ssim_from(const PixelErrors& errors) {
  const int width = errors.width, height = errors.height;
  const int w = std::min(width, kWindow), h = std::min(height, kWindow);
  std::vector<int> xs = window_starts(width), ys = window_starts(height);
  // Per-row sums added in order keep the mean independent of the schedule.
  std::vector<double> row_sums(ys.size(), 0.0);
  parallel_for(static_cast<long>(ys.size()), 0, [&](long r0, long r1) {
    for (long r = r0; r < r1; ++r) {
      size_t row = static_cast<size_t>(ys[r]) * width;
      for (int x : xs)
        row_sums[r] += window_ssim(errors.luminance_a.data() + row + x,
                                   errors.luminance_b.data() + row + x, width, w, h);
    }
  });
  double total = 0.0;
  for (double s : row_sums) total += s;
  return total / (double(xs.size()) * ys.size());
}

double ssim(const Image& a, const Image& b) {
  return ssim_from(measure_pixel_errors(a, b, true));
}

}  // namespace imx
