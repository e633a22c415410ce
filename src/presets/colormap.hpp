// Colour maps: a value t in [0, 1] to linear RGB. The one place that names them (scene files'
// "colormap" on planes and transfer functions, colour bars). Pure and allocation-free, for
// per-pixel code. Where each comes from: scripts/gen-colormap-tables. Every map is defined by
// display (sRGB) colours and decoded (core/colour.hpp): the tables when generated, grey here.
#pragma once
#include <algorithm>
#include <array>
#include <optional>
#include <string_view>

#include <glm/vec3.hpp>

#include "core/colour.hpp"
#include "intermix/scene.hpp"
#include "presets/colormap_tables.hpp"

namespace imx {

// The scene-file names of the colour maps, in Colormap's order.
inline constexpr std::array<std::string_view, 9> kColormapNames = {
    "grey", "hot",      "inferno",    "viridis",       "plasma",
    "jet",  "cold-hot", "red-yellow", "blue-lightblue"};

// The colour map called `name` (one of kColormapNames), if any.
inline std::optional<Colormap> find_colormap(std::string_view name) {
  for (size_t i = 0; i < kColormapNames.size(); ++i)
    if (name == kColormapNames[i]) return static_cast<Colormap>(i);
  return std::nullopt;
}

inline std::string_view colormap_name(Colormap map) {
  return kColormapNames[static_cast<size_t>(map)];
}

// A signed map: its lower half colours negative values, its upper half positive ones (cold-hot).
inline bool colormap_is_diverging(Colormap map) {
  return map == Colormap::cold_hot;
}

// The colour of `t` (clamped to [0, 1]; NaN gives the first entry): grey is the display grey
// (t, t, t), so a window's middle shows as mid-grey (128) as in every viewer; the others
// interpolate linearly between their 256 entries, entry i sitting at t = i / 255.
inline glm::vec3 colormap_rgb(Colormap map, float t) {
  t = t > 0.0f ? std::min(t, 1.0f) : 0.0f;
  if (map == Colormap::grey) return glm::vec3(srgb_decode(t));
  static constexpr const detail::ColormapEntry* kTables[] = {
      nullptr,      detail::kHot,     detail::kInferno,   detail::kViridis,      detail::kPlasma,
      detail::kJet, detail::kColdHot, detail::kRedYellow, detail::kBlueLightblue};
  static_assert(std::size(kTables) == kColormapNames.size());
  const detail::ColormapEntry* table = kTables[static_cast<size_t>(map)];
  const float x = t * static_cast<float>(detail::kColormapSize - 1);
  const int i = std::min(static_cast<int>(x), detail::kColormapSize - 2);
  const float f = x - static_cast<float>(i);
  const detail::ColormapEntry& a = table[i];
  const detail::ColormapEntry& b = table[i + 1];
  return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
}

}  // namespace imx
