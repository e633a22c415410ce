#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include <glm/common.hpp>

#include "core/colour.hpp"
#include "core/parallel.hpp"
#include "intermix/error.hpp"
#include "intermix/metrics.hpp"
#include "metrics/display_values.hpp"

namespace imx {

namespace {

// Heat in [0,1] in display space: black -> red -> yellow -> white, one third each.
glm::vec3 heat_colour(float heat) {
  float t = 3.0f * heat;
  return {std::clamp(t, 0.0f, 1.0f), std::clamp(t - 1.0f, 0.0f, 1.0f),
          std::clamp(t - 2.0f, 0.0f, 1.0f)};
}

}  // namespace

Image error_heat_map(const Image& a, const Image& b, double scale) {
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw Error(fmt::format("error_heat_map: scale must be positive and finite, got {}", scale));
  require_comparable(a, b);
  Image heat_map(a.width(), a.height());
  parallel_for(static_cast<long>(a.size()), 0, [&](long i0, long i1) {
    for (long i = i0; i < i1; ++i) {
      glm::vec3 diff = glm::abs(display_rgb(a.data()[i]) - display_rgb(b.data()[i]));
      float e = std::max({diff.r, diff.g, diff.b});
      glm::vec3 c = heat_colour(float(std::clamp(e * scale, 0.0, 1.0)));
      // The image is linear, so decode the display colour for write_png to show it as built.
      heat_map.data()[i] = glm::vec4(display_to_linear(c), 1.0f);
    }
  });
  return heat_map;
}

}  // namespace imx
