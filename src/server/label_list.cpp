#include "server/label_list.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <variant>

#include "core/colour.hpp"
#include "scene/label_map_parser.hpp"

namespace imx::server {

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

nlohmann::json label_list_json(const LabelMap& map, const std::vector<int32_t>& values) {
  nlohmann::json list = nlohmann::json::array();
  for (int32_t value : values) {
    const LabelEntry e = scene_json::label_entry(map, value);
    const glm::vec3 c = linear_to_display(e.color);  // as the table gives it
    list.push_back({{"value", e.value},
                    {"name", e.name},
                    {"color", {c.r, c.g, c.b}},
                    {"opacity", e.opacity},
                    {"visible", e.visible}});
  }
  return list;
}

}  // namespace imx::server
