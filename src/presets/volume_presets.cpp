#include "presets/volume_presets.hpp"

#include "presets/preset_name.hpp"

namespace imx {

std::vector<std::string> volume_preset_names() {
  std::vector<std::string> names;
  for (const detail::VolumePresetData& p : detail::volume_preset_table())
    names.push_back(preset_key(p.name));
  return names;
}

std::optional<SlicerVolumeProperty> find_volume_preset(std::string_view name) {
  const std::string key = preset_key(name);
  for (const detail::VolumePresetData& d : detail::volume_preset_table()) {
    if (preset_key(d.name) != key) continue;
    SlicerVolumeProperty p;
    p.name = std::string(d.name);
    p.scalar_opacity = slicer_opacity_points(d.scalar_opacity);
    p.gradient_opacity = slicer_opacity_points(d.gradient_opacity);
    p.color = slicer_color_points(d.color);
    p.shade = d.shade;
    p.ambient = d.ambient;
    p.diffuse = d.diffuse;
    p.specular = d.specular;
    p.specular_power = d.specular_power;
    if (d.range_lo < d.range_hi) p.effective_range = glm::dvec2(d.range_lo, d.range_hi);
    return p;
  }
  return std::nullopt;
}

}  // namespace imx
