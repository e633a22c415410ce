#include "annotate/scene_colour_bars.hpp"

#include <algorithm>
#include <limits>

#include "presets/colormap.hpp"
#include "raster/shade_fragment.hpp"
#include "volume/tf_lut.hpp"

namespace imx {

std::optional<ColourBar> volume_colour_bar(const VolumeObject& volume) {
  const std::vector<TfPoint>& p = volume.transfer_function.points;
  if (volume.style == VolumeStyle::iso || p.size() < 2 || !(p.front().value < p.back().value))
    return std::nullopt;
  const auto shows = [](const TfPoint& q) { return q.rgba.a > 0.0f; };
  const auto first = std::find_if(p.begin(), p.end(), shows);
  if (first == p.end()) return std::nullopt;
  const auto last = std::find_if(p.rbegin(), p.rend(), shows).base() - 1;
  ColourBar bar;
  bar.name = volume.name;
  bar.units = volume.units;
  bar.lo = (first == p.begin() ? first : first - 1)->value;
  bar.hi = (last + 1 == p.end() ? last : last + 1)->value;
  if (!(bar.lo < bar.hi)) {  // one shown point: the whole function's span
    bar.lo = p.front().value;
    bar.hi = p.back().value;
  }
  bar.colour = [tf = volume.transfer_function](double v) {
    return evaluate_transfer_function(tf, v);
  };
  return bar;
}

std::optional<ColourBar> plane_colour_bar(const Scene& scene, const PlaneObject& plane) {
  if (plane.volume < 0 || static_cast<size_t>(plane.volume) >= scene.volumes.size() ||
      !(plane.opacity > 0.0f) || !(plane.window.y > 0.0))
    return std::nullopt;
  if (plane.colormap == Colormap::grey) return std::nullopt;
  const VolumeObject& volume = scene.volumes[static_cast<size_t>(plane.volume)];
  ColourBar bar;
  bar.name = volume.name;
  bar.units = volume.units;
  bar.shown_by = plane.name;
  bar.lo = plane.window.x - 0.5 * plane.window.y;
  bar.hi = plane.window.x + 0.5 * plane.window.y;
  // The rasterizer's own arithmetic (shade_fragment.hpp), so the bar shows what the plane does.
  const auto threshold =
      static_cast<float>(plane.threshold.value_or(-std::numeric_limits<double>::infinity()));
  bar.colour = [plane, threshold](double v) {
    const auto value = static_cast<float>(v);
    if (!plane_value_shown(value, threshold, plane.symmetric)) return glm::vec4(0.0f);
    const float t =
        window_level(value, static_cast<float>(plane.window.x), static_cast<float>(plane.window.y));
    return glm::vec4(colormap_rgb(plane.colormap, t) * plane.color, 1.0f);
  };
  return bar;
}

std::vector<ColourBar> scene_colour_bars(const Scene& scene) {
  std::vector<ColourBar> bars;
  for (const ObjectRef& ref : scene.order) {
    std::optional<ColourBar> bar;
    if (ref.kind == ObjectKind::volume)
      bar = volume_colour_bar(scene.volumes.at(static_cast<size_t>(ref.index)));
    else if (ref.kind == ObjectKind::plane)
      bar = plane_colour_bar(scene, scene.planes.at(static_cast<size_t>(ref.index)));
    if (bar) bars.push_back(std::move(*bar));
  }
  return bars;
}

}  // namespace imx
