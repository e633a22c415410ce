#include "volume/projection_tables.hpp"

#include <algorithm>
#include <cmath>

namespace imx {

namespace {

// A hundredth of an entry: the margin that keeps each bound on its safe side of rounding.
constexpr float kMargin = 0.01f;

}  // namespace

ProjectionLimits projection_limits(const TfLut& lut) {
  const std::vector<glm::vec4>& e = lut.entries();
  ProjectionLimits p;
  if (e.empty()) return p;
  const int n = static_cast<int>(e.size());
  auto value_at = [&](float entry) { return lut.lo() + entry / lut.inv_step(); };
  int first = 0, last = n - 1;
  while (first < n && !(e[first].a > 0.0f)) ++first;
  while (last >= 0 && !(e[last].a > 0.0f)) --last;
  if (first == n) {  // nothing shows: every bound holds everywhere
    p.invisible_up_to = INFINITY;
    p.invisible_from = -INFINITY;
  } else {
    // lookup() interpolates entries i and i + 1: it is 0 up to the entry before the first one.
    if (first > 0) p.invisible_up_to = value_at(static_cast<float>(first - 1) - kMargin);
    if (last < n - 1) p.invisible_from = value_at(static_cast<float>(last + 1) + kMargin);
    const auto shows = [](const glm::vec4& c) { return c.a > 0.0f; };
    p.invisible_only_below = std::all_of(e.begin() + first, e.end(), shows);
    p.invisible_only_above = std::all_of(e.begin(), e.begin() + last + 1, shows);
  }
  int top = n - 1, bottom = 0;
  while (top > 0 && e[top - 1] == e[n - 1]) --top;
  while (bottom < n - 1 && e[bottom + 1] == e[0]) ++bottom;
  p.constant_from = top == 0 ? -INFINITY : value_at(static_cast<float>(top) + kMargin);
  p.constant_up_to = bottom == n - 1 ? INFINITY : value_at(static_cast<float>(bottom) - kMargin);
  return p;
}

AttenuationTable::AttenuationTable(const TfLut& lut) : lo_(lut.lo()), inv_step_(lut.inv_step()) {
  // Opacity 1 would be an infinite attenuation: it is held just below, where a millimetre
  // already lets through less than one part in 10^6.
  constexpr float kMaxOpacity = 1.0f - 1e-6f;
  const float per_mm = 1.0f / std::max(lut.unit_distance(), 1e-6f);
  table_.reserve(lut.entries().size());
  for (const glm::vec4& c : lut.entries()) {
    const float a = std::clamp(c.a, 0.0f, kMaxOpacity);
    const float mu = -std::log1p(-a) * per_mm;
    table_.push_back(glm::vec4(glm::vec3(c) * mu, mu));
  }
}

}  // namespace imx
