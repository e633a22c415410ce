// Colour maps for planes (grey, hot, inferno, viridis): a windowed value t in [0, 1] to linear
// RGB. Pure and allocation-free, for per-pixel code.
#pragma once
#include <algorithm>
#include <array>
#include <string_view>

#include <glm/vec3.hpp>

#include "intermix/scene.hpp"
#include "presets/colormap_tables.hpp"

namespace imx {

// The scene-file names of the colour maps, in Colormap's order.
inline constexpr std::array<std::string_view, 4> kColormapNames = {"grey", "hot", "inferno",
                                                                   "viridis"};

// The colour of `t` (clamped to [0, 1]; NaN gives the first entry): grey is (t, t, t); the
// others interpolate linearly between their 256 entries, entry i sitting at t = i / 255.
inline glm::vec3 colormap_rgb(Colormap map, float t) {
  t = t > 0.0f ? std::min(t, 1.0f) : 0.0f;
  if (map == Colormap::grey) return glm::vec3(t);
  const detail::ColormapEntry* table = map == Colormap::hot       ? detail::kHot
                                       : map == Colormap::inferno ? detail::kInferno
                                                                  : detail::kViridis;
  const float x = t * static_cast<float>(detail::kColormapSize - 1);
  const int i = std::min(static_cast<int>(x), detail::kColormapSize - 2);
  const float f = x - static_cast<float>(i);
  const detail::ColormapEntry& a = table[i];
  const detail::ColormapEntry& b = table[i + 1];
  return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
}

}  // namespace imx
