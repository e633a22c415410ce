#include "labels/present_labels.hpp"

#include <cmath>
#include <iterator>
#include <set>
#include <variant>

namespace imx {

std::vector<int32_t> present_labels(const VolumeData& data) {
  std::set<int32_t> found;
  std::visit(
      [&](const auto& voxels) {
        const auto* v = voxels.data();
        for (size_t i = 0; i < voxels.size(); ++i) {
          const double x = static_cast<double>(v[i]);
          if (!(std::abs(x) < 2147483647.0) || x != std::floor(x)) continue;
          if (found.insert(static_cast<int32_t>(x)).second && found.size() > kMaxListedLabels)
            found.erase(std::prev(found.end()));  // keep the lowest values
        }
      },
      data.voxels);
  return {found.begin(), found.end()};
}

}  // namespace imx
