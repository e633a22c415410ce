#include "presets/tf_merge.hpp"

#include <algorithm>
#include <vector>

#include "intermix/error.hpp"

namespace imx {
namespace {

// f at x, approached from the left or from the right (they differ only at a step); the first
// and last points beyond the ends.
template <class P>
P evaluate(std::span<const P> f, double x, bool from_right) {
  auto lo = std::lower_bound(f.begin(), f.end(), x, [](const P& p, double v) { return p.x < v; });
  auto hi = std::upper_bound(lo, f.end(), x, [](double v, const P& p) { return v < p.x; });
  if (lo != hi) return from_right ? *(hi - 1) : *lo;
  if (lo == f.begin()) return f.front();
  if (lo == f.end()) return f.back();
  const P& a = *(lo - 1);
  const P& b = *lo;
  return a + ((x - a.x) / (b.x - a.x)) * (b - a);
}

TfPoint point(double value, const glm::dvec4& color, const glm::dvec2& opacity) {
  return {value, glm::vec4(glm::vec3(color.y, color.z, color.w), static_cast<float>(opacity.y))};
}

}  // namespace

TransferFunction merge_opacity_and_color(std::span<const glm::dvec2> opacity,
                                         std::span<const glm::dvec4> color) {
  if (opacity.empty() || color.empty())
    throw Error("merge_opacity_and_color: both functions need at least one point");
  std::vector<double> values;
  values.reserve(opacity.size() + color.size());
  for (const glm::dvec2& p : opacity) values.push_back(p.x);
  for (const glm::dvec4& p : color) values.push_back(p.x);
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  TransferFunction tf;
  for (double x : values) {
    glm::dvec2 a_left = evaluate(opacity, x, false), a_right = evaluate(opacity, x, true);
    glm::dvec4 c_left = evaluate(color, x, false), c_right = evaluate(color, x, true);
    tf.points.push_back(point(x, c_left, a_left));
    if (a_left != a_right || c_left != c_right) tf.points.push_back(point(x, c_right, a_right));
  }
  return tf;
}

}  // namespace imx
