#include <algorithm>
#include <cmath>

#include "core/colour.hpp"
#include "volume/label_classifier.hpp"

namespace imx {
namespace {

// The widest run of label values kept as a dense array; wider tables are searched.
constexpr int64_t kMaxDenseSpan = int64_t{1} << 16;
// Palette looks precomputed for 0 .. kPaletteDense - 1 (the labels of most segmentations).
constexpr int64_t kPaletteDense = 256;

}  // namespace

glm::vec3 default_label_color(int32_t value) {
  // Hue by the golden angle, so consecutive labels are far apart on the colour wheel; brightness
  // and saturation cycle with period 3 and 2, so labels whose hues come close again still differ.
  const int64_t k = static_cast<int64_t>(value) - 1;
  const double h = std::fmod(static_cast<double>(k) * 0.618033988749895, 1.0);
  const double hue = (h < 0.0 ? h + 1.0 : h) * 6.0;
  const int m3 = static_cast<int>(((k % 3) + 3) % 3), m2 = static_cast<int>(((k % 2) + 2) % 2);
  const double v = m3 == 0 ? 0.95 : m3 == 1 ? 0.8 : 0.65;
  const double s = m2 == 0 ? 0.75 : 0.55;
  const int sector = static_cast<int>(hue) % 6;
  const double f = hue - std::floor(hue);
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r = v, g = t, b = p;
  switch (sector) {
    case 1:
      r = q, g = v, b = p;
      break;
    case 2:
      r = p, g = v, b = t;
      break;
    case 3:
      r = p, g = q, b = v;
      break;
    case 4:
      r = t, g = p, b = v;
      break;
    case 5:
      r = v, g = p, b = q;
      break;
    default:
      break;
  }
  return display_to_linear(
      glm::vec3(static_cast<float>(r), static_cast<float>(g), static_cast<float>(b)));
}

LabelLooks::LabelLooks(const LabelMap& map)
    : active_(true),
      nearest_(map.interpolation == LabelInterpolation::nearest),
      palette_(map.palette_unlisted),
      shown_(map.shown),
      unit_distance_(static_cast<float>(map.unit_distance)) {
  for (const LabelEntry& e : map.entries)
    listed_.push_back({e.value, e.visible ? glm::vec4(e.color, e.opacity) : glm::vec4(0.0f)});
  std::sort(listed_.begin(), listed_.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  bool zero_listed = false;
  for (const auto& [value, look] : listed_) {
    (look.a > 0.0f ? shown_listed_ : unshown_listed_).push_back(value);
    zero_listed |= value == 0;
    max_opacity_ = std::max(max_opacity_, look.a);
  }
  if (!zero_listed) {  // background: hidden unless listed
    unshown_listed_.insert(std::lower_bound(unshown_listed_.begin(), unshown_listed_.end(), 0), 0);
  }
  if (palette_) max_opacity_ = 1.0f;
  int64_t lo = listed_.empty() ? 0 : listed_.front().first;
  int64_t hi = listed_.empty() ? 0 : listed_.back().first;
  if (palette_) lo = std::min<int64_t>(lo, 0), hi = std::max<int64_t>(hi, kPaletteDense - 1);
  if (hi - lo + 1 <= kMaxDenseSpan) {
    lo_ = lo;
    dense_.resize(static_cast<size_t>(hi - lo + 1));
    for (int64_t v = lo; v <= hi; ++v)
      dense_[static_cast<size_t>(v - lo)] = look_outside(static_cast<int32_t>(v));
  }
}

glm::vec4 LabelLooks::look_outside(int32_t label) const {
  auto it = std::lower_bound(listed_.begin(), listed_.end(), label,
                             [](const auto& e, int32_t v) { return e.first < v; });
  if (it != listed_.end() && it->first == label) return it->second;
  if (!palette_ || label == 0) return glm::vec4(0.0f);
  return glm::vec4(default_label_color(label), 1.0f);
}

bool LabelLooks::any_shown_in(float lo, float hi) const {
  if (!(lo <= hi)) return true;  // NaN: never call a brick empty on it
  const double a = std::ceil(static_cast<double>(lo)), b = std::floor(static_cast<double>(hi));
  if (a > b) return false;
  auto count = [&](const std::vector<int32_t>& v) {
    return std::upper_bound(v.begin(), v.end(), b) - std::lower_bound(v.begin(), v.end(), a);
  };
  if (!palette_) return count(shown_listed_) > 0;
  return b - a + 1.0 > static_cast<double>(count(unshown_listed_));
}

}  // namespace imx
