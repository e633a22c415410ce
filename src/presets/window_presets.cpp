#include "presets/window_presets.hpp"

#include "presets/preset_name.hpp"

namespace imx {

std::vector<std::string> window_preset_names() {
  std::vector<std::string> names;
  for (const detail::WindowPresetData& p : detail::window_preset_table())
    names.push_back(preset_key(p.name));
  return names;
}

std::optional<glm::dvec2> find_window_preset(std::string_view name) {
  const std::string key = preset_key(name);
  for (const detail::WindowPresetData& p : detail::window_preset_table())
    if (preset_key(p.name) == key) return glm::dvec2(p.level, p.window);
  return std::nullopt;
}

}  // namespace imx
