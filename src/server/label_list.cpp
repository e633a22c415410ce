#include "server/label_list.hpp"

#include "core/colour.hpp"
#include "scene/label_map_parser.hpp"

namespace imx::server {

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
