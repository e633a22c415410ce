#include "presets/slicer_volume_property.hpp"

#include <algorithm>

#include "core/colour.hpp"
#include "presets/tf_merge.hpp"

namespace imx {
namespace {

// Groups of N numbers as points; equal x replaces the point before (VTK's AddPoint).
template <int N>
std::vector<glm::vec<N, double>> points_of(std::span<const double> flat) {
  std::vector<glm::vec<N, double>> out;
  for (size_t i = 0; i + N <= flat.size(); i += N) {
    glm::vec<N, double> p;
    for (int c = 0; c < N; ++c) p[c] = flat[i + static_cast<size_t>(c)];
    if (!out.empty() && out.back().x == p.x)
      out.back() = p;
    else
      out.push_back(p);
  }
  return out;
}

}  // namespace

std::vector<glm::dvec2> slicer_opacity_points(std::span<const double> flat) {
  return points_of<2>(flat);
}

std::vector<glm::dvec4> slicer_color_points(std::span<const double> flat) {
  return points_of<4>(flat);
}

bool gradient_opacity_is_trivial(const SlicerVolumeProperty& p) {
  // Piecewise linear and constant beyond its ends: its least value on [0, inf) is at 0 or at a
  // point >= 0.
  const auto& g = p.gradient_opacity;
  if (g.empty()) return true;
  auto at_zero = [&] {
    if (g.front().x >= 0.0) return g.front().y;
    for (size_t i = 1; i < g.size(); ++i)
      if (g[i].x >= 0.0)
        return g[i - 1].y + (0.0 - g[i - 1].x) / (g[i].x - g[i - 1].x) * (g[i].y - g[i - 1].y);
    return g.back().y;
  };
  if (at_zero() != 1.0) return false;
  for (const glm::dvec2& q : g)
    if (q.x >= 0.0 && q.y != 1.0) return false;
  return true;
}

TransferFunction to_transfer_function(const SlicerVolumeProperty& p) {
  TransferFunction tf = merge_opacity_and_color(p.scalar_opacity, p.color);
  // Slicer's colours are display colours: decoded after the merge, so that each merged point
  // is the colour Slicer shows at its value.
  for (TfPoint& point : tf.points) point.rgba = display_to_linear(point.rgba);
  tf.unit_distance = 1.0;
  return tf;
}

Shading to_shading(const SlicerVolumeProperty& p) {
  Shading s;
  s.enabled = p.shade;
  s.ambient = static_cast<float>(p.ambient);
  s.diffuse = static_cast<float>(p.diffuse);
  s.specular = static_cast<float>(p.specular);
  s.shininess = static_cast<float>(p.specular_power);
  return s;
}

double adjust_centre(const SlicerVolumeProperty& p) {
  if (p.effective_range) return 0.5 * (p.effective_range->x + p.effective_range->y);
  double lo = p.scalar_opacity.front().x, hi = p.scalar_opacity.back().x;
  if (!p.color.empty()) {
    lo = std::min(lo, p.color.front().x);
    hi = std::max(hi, p.color.back().x);
  }
  return 0.5 * (lo + hi);
}

}  // namespace imx
