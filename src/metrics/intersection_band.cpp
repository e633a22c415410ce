#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "intermix/band_metrics.hpp"
#include "intermix/error.hpp"
#include "metrics/display_values.hpp"

namespace imx {

std::vector<uint8_t> intersection_band(const Image& depth_a, const Image& depth_b, int radius) {
  require_comparable(depth_a, depth_b);
  const int w = depth_a.width(), h = depth_a.height();
  // -1: neither or one object only; 0: a is nearer; 1: b is nearer
  std::vector<int8_t> nearer(static_cast<size_t>(w) * h, -1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float a = depth_a.at(x, y).r, b = depth_b.at(x, y).r;
      if (std::isfinite(a) && std::isfinite(b)) nearer[static_cast<size_t>(y) * w + x] = b < a;
    }
  std::vector<uint8_t> curve(nearer.size(), 0);
  auto at = [&](int x, int y) { return nearer[static_cast<size_t>(y) * w + x]; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int8_t n = at(x, y);
      if (n < 0) continue;
      bool edge = (x + 1 < w && at(x + 1, y) >= 0 && at(x + 1, y) != n) ||
                  (y + 1 < h && at(x, y + 1) >= 0 && at(x, y + 1) != n);
      if (edge) curve[static_cast<size_t>(y) * w + x] = 1;
    }
  radius = std::max(radius, 0);
  std::vector<uint8_t> band(curve.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!curve[static_cast<size_t>(y) * w + x]) continue;
      for (int j = std::max(0, y - radius); j <= std::min(h - 1, y + radius); ++j)
        for (int i = std::max(0, x - radius); i <= std::min(w - 1, x + radius); ++i)
          band[static_cast<size_t>(j) * w + i] = 1;
    }
  return band;
}

double masked_psnr(const Image& a, const Image& b, std::span<const uint8_t> mask) {
  require_comparable(a, b);
  if (mask.size() != a.size())
    throw Error(
        fmt::format("masked PSNR: the mask has {} pixels, the images {}", mask.size(), a.size()));
  double sum = 0.0;
  long count = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (!mask[i]) continue;
    glm::vec3 d = display_rgb(a.data()[i]) - display_rgb(b.data()[i]);
    sum += static_cast<double>(d.r) * d.r + static_cast<double>(d.g) * d.g +
           static_cast<double>(d.b) * d.b;
    ++count;
  }
  if (count == 0) return std::numeric_limits<double>::quiet_NaN();
  double mse = sum / (3.0 * static_cast<double>(count));
  if (mse == 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(1.0 / mse);
}

}  // namespace imx
