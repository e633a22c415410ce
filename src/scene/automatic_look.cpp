#include "scene/automatic_look.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <variant>

#include <fmt/format.h>

#include "volume/value_sample.hpp"

namespace imx {
namespace {

using Json = nlohmann::json;

// Short decimal numbers in the document (9 significant digits), not 17-digit doubles.
double tidy(double v) {
  return std::stod(fmt::format("{:.9g}", v));
}

Json point(double value, double r, double g, double b, double a) {
  return Json::array({tidy(value), r, g, b, a});
}

Json lit_shading() {
  return {{"ambient", 0.3}, {"diffuse", 0.7}, {"specular", 0.2}, {"shininess", 24}};
}

}  // namespace

bool looks_like_label_map(const VolumeData& data) {
  if (data.colours) return false;  // a colour volume's scalars are its luminance
  constexpr size_t kMostLabels = 256;
  std::set<int64_t> values;
  const bool integers = std::visit(
      [&](const auto& voxels) {
        const auto* v = voxels.data();
        for (size_t i = 0; i < voxels.size(); ++i) {
          const double x = static_cast<double>(v[i]);
          if (!(std::abs(x) < 1e9) || x != std::floor(x)) return false;
          if (values.insert(static_cast<int64_t>(x)).second && values.size() > kMostLabels)
            return false;
        }
        return true;
      },
      data.voxels);
  if (!integers || values.size() < 3) return false;
  const double span = static_cast<double>(*values.rbegin() - *values.begin() + 1);
  return values.size() <= 16 || static_cast<double>(values.size()) <= 0.5 * span;
}

AutomaticLook automatic_look(const VolumeData& data, std::string_view modality,
                             std::string_view units) {
  if (data.colours)  // its own colours; opacity rising with luminance, black clear (as NiiVue)
    return {{{"points", Json::array({point(0, 1, 1, 1, 0), point(255, 1, 1, 1, 1)})}},
            nullptr,
            "a colour volume: its colours, opacity rising with luminance"};
  constexpr std::array<double, 6> kFractions = {0.001, 0.02, 0.5, 0.98, 0.995, 0.999};
  const std::vector<double> q = value_percentiles(data, kFractions);
  const auto [lowest, highest] = data.range();
  if (!q.empty() && !(q[5] > q[0]) && lowest < q[0]) {
    // One value above a background (a binary mask): its boundary as a shaded surface.
    const double v = q[0], half = 0.5 * (lowest + v);
    return {{{"points", Json::array({point(half, 1, 0.8, 0.45, 0), point(v, 1, 0.8, 0.45, 0.8)})}},
            lit_shading(),
            fmt::format("a mask: the voxels of value {:g} as a surface", tidy(v))};
  }
  if (q.empty() || !(q[5] > q[0])) {
    // No finite voxel, or one value everywhere: a faint grey wherever there is data.
    const double v = q.empty() ? 0.0 : q[0];
    return {
        {{"points", Json::array({point(v - 1.0, 1, 1, 1, 0.02), point(v + 1.0, 1, 1, 1, 0.02)})}},
        nullptr,
        "constant values: a faint grey"};
  }
  const double p001 = q[0], p02 = q[1], p50 = q[2], p98 = q[3], p995 = q[4], p999 = q[5];
  const bool looks_like_hu = p001 <= -500.0 && p999 >= 100.0 && p001 >= -3100.0;
  if (modality == "CT" || units == "HU" || (modality.empty() && looks_like_hu))
    return {{{"preset", "ct-bone"}},
            nullptr,
            fmt::format("CT ({}): preset ct-bone",
                        units == "HU"      ? "units HU"
                        : modality == "CT" ? "modality CT"
                                           : fmt::format("values {:g} to {:g}", p001, p999))};

  if (modality == "PT" || units == "g/ml" || units == "BQML") {
    const double lo = std::max(p50, 0.0), hi = std::max(p995, lo + 1e-6), r = hi - lo;
    return {{{"points",
              Json::array({point(lo, 0, 0, 0, 0), point(lo + 0.3 * r, 0.8, 0.05, 0, 0.03),
                           point(lo + 0.65 * r, 1, 0.55, 0, 0.25), point(hi, 1, 1, 0.75, 0.6)})}},
            nullptr,
            fmt::format("PET: a hot ramp over {:g} to {:g}", lo, hi)};
  }

  const bool signed_map = data.type() == VoxelType::f32 && p001 < 0.0 && p999 > 0.0 &&
                          std::min(-p001, p999) > 0.25 * std::max(-p001, p999);
  if (signed_map) {
    const double a = std::max(-p001, p999), t = 0.4 * a, gap = 1e-4 * a;
    return {{{"points", Json::array({point(-a, 0.55, 0.85, 1, 0.8), point(-t, 0, 0.25, 1, 0.3),
                                     point(-t + gap, 0, 0, 0, 0), point(t - gap, 0, 0, 0, 0),
                                     point(t, 1, 0, 0, 0.3), point(a, 1, 1, 0, 0.8)})}},
            lit_shading(),
            fmt::format("a signed map: shown beyond +/-{:g}", tidy(t))};
  }

  const double lo = p02, hi = std::max(p98, p02 + 1e-6), r = hi - lo;
  return {{{"points",
            Json::array({point(lo + 0.1 * r, 0.3, 0.3, 0.3, 0),
                         point(lo + 0.5 * r, 0.75, 0.75, 0.75, 0.08), point(hi, 1, 1, 1, 0.5)})}},
          lit_shading(),
          fmt::format("a grey ramp over the robust range {:g} to {:g}", tidy(lo), tidy(hi))};
}

}  // namespace imx
