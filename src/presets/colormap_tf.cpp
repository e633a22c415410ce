#include "presets/colormap_tf.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "presets/colormap.hpp"

namespace imx {
namespace {

// One side's sample at magnitude m: the colour for +m and for -m, and the opacity.
struct SideSample {
  double m;
  glm::vec3 positive, negative;
  float alpha;
};

// Where in the map a side's fraction s lands: the whole map, or a diverging map's halves.
float map_position(const ColormapTransferFunction& c, double s, bool negative) {
  if (!c.symmetric || !colormap_is_diverging(c.map)) return static_cast<float>(s);
  const double half = static_cast<double>(detail::kColormapSize / 2);  // 128
  const double last = static_cast<double>(detail::kColormapSize - 1);  // 255
  return static_cast<float>(negative ? (half - 1.0 - (half - 1.0) * s) / last
                                     : (half + (half - 1.0) * s) / last);
}

SideSample sample_at(const ColormapTransferFunction& c, double m) {
  const double s = std::clamp((m - c.lo) / (c.hi - c.lo), 0.0, 1.0);
  return {m, colormap_rgb(c.map, map_position(c, s, false)),
          colormap_rgb(c.map, map_position(c, s, true)), c.opacity * static_cast<float>(s)};
}

}  // namespace

TransferFunction colormap_transfer_function(const ColormapTransferFunction& c) {
  if (!(std::isfinite(c.lo) && std::isfinite(c.hi) && c.lo < c.hi))
    throw Error(fmt::format("range [{}, {}] must be finite with its first value below its second",
                            c.lo, c.hi));
  if (c.symmetric && c.lo < 0.0)
    throw Error(
        fmt::format("range [{}, {}]: symmetric ranges are magnitudes, so they start at 0 "
                    "or above",
                    c.lo, c.hi));
  if (c.threshold && !(std::isfinite(*c.threshold) && *c.threshold <= c.hi))
    throw Error(fmt::format("threshold {} hides every value: it must be at most the range's end {}",
                            *c.threshold, c.hi));
  if (c.threshold && c.symmetric && *c.threshold < 0.0)
    throw Error(fmt::format("threshold {}: a symmetric threshold is a magnitude, 0 or above",
                            *c.threshold));
  if (!(c.opacity >= 0.0f && c.opacity <= 1.0f))
    throw Error(fmt::format("opacity {} is not in [0, 1]", c.opacity));

  // The shown magnitudes start at `cut`; a threshold above lo makes a step there.
  const double cut = std::max(c.lo, c.threshold.value_or(c.lo));
  const bool step = cut > c.lo;
  const int samples = c.symmetric && colormap_is_diverging(c.map) ? detail::kColormapSize / 2
                                                                  : detail::kColormapSize;
  std::vector<SideSample> side{sample_at(c, cut)};
  for (int i = 0; i < samples; ++i) {
    const double m = c.lo + (c.hi - c.lo) * static_cast<double>(i) / (samples - 1);
    if (m > cut) side.push_back(sample_at(c, m));
  }

  TransferFunction tf;
  auto add = [&tf](double v, const glm::vec3& rgb, float a) {
    tf.points.push_back(TfPoint{v, glm::vec4(rgb, a)});
  };
  if (c.symmetric) {
    for (auto it = side.rbegin(); it != side.rend(); ++it) add(-it->m, it->negative, it->alpha);
    if (step) {
      add(std::nextafter(-cut, 0.0), side.front().negative, 0.0f);
      add(cut, side.front().positive, 0.0f);
    }
  } else if (step) {  // a float step below: the first point also rules every value below it
    add(std::nextafter(cut, -HUGE_VAL), side.front().positive, 0.0f);
  }
  for (const SideSample& s : side) add(s.m, s.positive, s.alpha);
  return tf;
}

}  // namespace imx
