#include "metrics/pixel_errors.hpp"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

#include "core/parallel.hpp"
#include "metrics/display_values.hpp"

namespace imx {

namespace {

struct RowErrors {
  double sum_squared = 0.0;
  float max_error = 0.0f;
  long over_1 = 0, over_4 = 0, over_16 = 0;
};

}  // namespace

PixelErrors measure_pixel_errors(const Image& a, const Image& b, bool with_luminance) {
  require_comparable(a, b);
  const int width = a.width(), height = a.height();
  PixelErrors result;
  result.width = width;
  result.height = height;
  if (with_luminance) {
    result.luminance_a.resize(a.size());
    result.luminance_b.resize(b.size());
  }
  // Per-row partial results summed in row order keep the totals independent of the schedule.
  std::vector<RowErrors> rows(height);
  parallel_for(height, 0, [&](long y0, long y1) {
    for (long y = y0; y < y1; ++y) {
      RowErrors& row = rows[y];
      size_t base = static_cast<size_t>(y) * width;
      for (int x = 0; x < width; ++x) {
        glm::vec3 da = display_rgb(a.data()[base + x]);
        glm::vec3 db = display_rgb(b.data()[base + x]);
        glm::vec3 diff = glm::abs(da - db);
        row.sum_squared +=
            double(diff.r) * diff.r + double(diff.g) * diff.g + double(diff.b) * diff.b;
        double e = std::max({diff.r, diff.g, diff.b});
        row.max_error = std::max(row.max_error, float(e));
        row.over_1 += e > 1.0 / 255.0;
        row.over_4 += e > 4.0 / 255.0;
        row.over_16 += e > 16.0 / 255.0;
        if (with_luminance) {
          result.luminance_a[base + x] = display_luminance(da);
          result.luminance_b[base + x] = display_luminance(db);
        }
      }
    }
  });
  for (const RowErrors& row : rows) {
    result.sum_squared += row.sum_squared;
    result.max_error = std::max(result.max_error, double(row.max_error));
    result.over_1 += row.over_1;
    result.over_4 += row.over_4;
    result.over_16 += row.over_16;
  }
  return result;
}

}  // namespace imx
