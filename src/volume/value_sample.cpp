#include "volume/value_sample.hpp"

namespace imx {

std::vector<double> value_percentiles(const VolumeData& data, std::span<const double> fractions) {
  constexpr double kMaxSamples = 1024.0 * 1024.0;
  std::vector<float> values;
  values.reserve(
      static_cast<size_t>(std::min(static_cast<double>(data.voxel_count()), 2.0 * kMaxSamples)));
  for_each_sampled_value(data, kMaxSamples,
                         [&](double s) { values.push_back(static_cast<float>(s)); });
  if (values.empty()) return {};
  const float lowest = *std::min_element(values.begin(), values.end());
  const auto background = std::count(values.begin(), values.end(), lowest);
  if (2 * static_cast<size_t>(background) >= values.size() &&
      static_cast<size_t>(background) < values.size())
    std::erase(values, lowest);
  std::vector<double> result;
  for (double f : fractions) {
    const double index = std::clamp(f, 0.0, 1.0) * static_cast<double>(values.size() - 1);
    auto nth = values.begin() + static_cast<std::ptrdiff_t>(std::llround(index));
    std::nth_element(values.begin(), nth, values.end());
    result.push_back(*nth);
  }
  return result;
}

}  // namespace imx
