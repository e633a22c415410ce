#include "volume/display_window.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "volume/value_sample.hpp"

namespace imx {
namespace {

constexpr double kMaxSamples = 1024.0 * 1024.0;

// The value below which `fraction` of `values` lie (reorders them).
double percentile(std::vector<float>& values, double fraction) {
  const double index = std::clamp(fraction, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  auto nth = values.begin() + static_cast<std::ptrdiff_t>(std::llround(index));
  std::nth_element(values.begin(), nth, values.end());
  return *nth;
}

// The 2nd to 98th percentile as [centre, width]; any width shows a single value.
glm::dvec2 robust_window(std::vector<float>& values) {
  const double lo = percentile(values, 0.02), hi = percentile(values, 0.98);
  if (hi > lo) return {0.5 * (lo + hi), hi - lo};
  return {lo, 1.0};
}

}  // namespace

InitialWindow initial_display_window(const VolumeData& data,
                                     const std::optional<glm::dvec2>& header_window) {
  InitialWindow out;
  std::vector<float> values;
  for_each_sampled_value(data, kMaxSamples,
                         [&](double s) { values.push_back(static_cast<float>(s)); });
  if (values.empty()) return out;
  const float lowest = *std::min_element(values.begin(), values.end());
  std::vector<float> above;  // above the background
  above.reserve(values.size());
  for (float v : values)
    if (v > lowest) above.push_back(v);
  out.background = lowest;
  if (above.empty()) {
    above = std::move(values);  // a constant volume: no background
    out.background = -INFINITY;
  } else {
    const double p1 = percentile(above, 0.01), p99 = percentile(above, 0.99);
    const double level = p1 + 0.1 * (p99 - p1);
    const auto tissue =
        std::count_if(above.begin(), above.end(), [&](float v) { return v > level; });
    if (tissue > 0) {
      std::erase_if(above, [&](float v) { return v <= level; });
      out.background = level;
    }
  }
  if (header_window && std::isfinite(header_window->x) && header_window->y > 0.0) {
    const double lo = header_window->x - 0.5 * header_window->y;
    const double hi = header_window->x + 0.5 * header_window->y;
    const auto inside =
        std::count_if(above.begin(), above.end(), [&](float v) { return v >= lo && v <= hi; });
    out.header_fraction = static_cast<double>(inside) / static_cast<double>(above.size());
    if (out.header_fraction >= kHeaderWindowMinFraction) {
      out.window = *header_window;
      out.from_header = true;
      return out;
    }
  }
  out.window = robust_window(above);
  if (header_window)
    out.note = fmt::format(
        "the header's window (L {:.6g} / W {:.6g}) holds {:.1f}% of the voxels above the "
        "background (> {:.6g}), under {:.0f}%: showing their 2nd-98th percentiles, L {:.6g} / "
        "W {:.6g}",
        header_window->x, header_window->y, 100.0 * out.header_fraction, out.background,
        100.0 * kHeaderWindowMinFraction, out.window.x, out.window.y);
  return out;
}

}  // namespace imx
