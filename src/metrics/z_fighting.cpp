#include "metrics/z_fighting.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "metrics/display_values.hpp"

namespace imx {

namespace {

// Mean and variance (summed over RGB) of f(x, y) over the region.
template <class F>
double region_std_dev(int w, int h, std::span<const uint8_t> region, F&& f) {
  glm::dvec3 sum(0.0), sum2(0.0);
  long n = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!region[size_t(y) * w + x]) continue;
      glm::dvec3 v = f(x, y);
      sum += v;
      sum2 += v * v;
      ++n;
    }
  if (n < 2) return 0.0;
  glm::dvec3 mean = sum / double(n);
  glm::dvec3 var = glm::max(sum2 / double(n) - mean * mean, glm::dvec3(0.0));
  return std::sqrt((var.x + var.y + var.z) / 3.0);
}

}  // namespace

ZFightingStats z_fighting(const Image& image, const Image& jittered,
                          std::span<const uint8_t> region) {
  require_comparable(image, jittered);
  const int w = image.width(), h = image.height();
  if (region.size() != image.size())
    throw Error(
        fmt::format("z-fighting: region has {} pixels, the images {}x{}", region.size(), w, h));
  auto display = [](const Image& im) {
    return [&im](int x, int y) { return glm::dvec3(display_rgb(im.at(x, y))); };
  };
  ZFightingStats s;
  for (uint8_t r : region) s.pixels += r ? 1 : 0;
  s.std_dev = region_std_dev(w, h, region, display(image));
  s.jittered_std_dev = region_std_dev(w, h, region, display(jittered));
  s.speckle = region_std_dev(w, h, region, [&](int x, int y) {
    glm::dvec3 mean(0.0);
    int n = 0;
    for (int j = std::max(y - 1, 0); j <= std::min(y + 1, h - 1); ++j)
      for (int i = std::max(x - 1, 0); i <= std::min(x + 1, w - 1); ++i, ++n)
        mean += glm::dvec3(display_rgb(image.at(i, j)));
    return glm::dvec3(display_rgb(image.at(x, y))) - mean / double(n);
  });
  double change = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (region[size_t(y) * w + x]) {
        glm::dvec3 d =
            glm::dvec3(display_rgb(image.at(x, y))) - glm::dvec3(display_rgb(jittered.at(x, y)));
        change += glm::dot(d, d) / 3.0;
      }
  s.jitter_change = s.pixels > 0 ? std::sqrt(change / double(s.pixels)) : 0.0;
  return s;
}

}  // namespace imx
