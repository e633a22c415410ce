// A test streamline object: one straight tube along x, its points valued by x and drawn
// unlit in grey, so that a pixel's grey says where along the tube it lies.
#pragma once
#include <memory>
#include <utility>
#include <vector>

#include "intermix/scene.hpp"
#include "intermix/streamlines.hpp"

namespace imx::test {

// One straight streamline along x from -10 to 10 at y = z = 0, points every 0.5 mm, valued x.
inline StreamlineObject rod(double radius, float opacity) {
  Streamlines s;
  std::vector<float> values;
  for (int i = 0; i <= 40; ++i) {
    s.points.push_back({-10.0f + 0.5f * i, 0.0f, 0.0f});
    values.push_back(-10.0f + 0.5f * i);
  }
  s.offsets = {0, static_cast<uint32_t>(s.points.size())};
  s.point_values.push_back({"x", values});
  StreamlineObject o;
  o.name = "rod";
  o.radius = radius;
  o.opacity = opacity;
  o.shading.enabled = false;
  o.colouring = StreamlineColouring::point_value;
  o.value = "x";
  o.colormap = Colormap::grey;
  o.range = glm::dvec2(-10.0, 10.0);
  o.streamlines = std::make_shared<const Streamlines>(std::move(s));
  return o;
}

}  // namespace imx::test
