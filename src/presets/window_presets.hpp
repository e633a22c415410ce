// 3D Slicer's window/level presets for slices (CT-Brain, CT-Lung, ...), looked up by name.
#pragma once
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

namespace imx {

namespace detail {

struct WindowPresetData {
  std::string_view name;  // Slicer's name, e.g. "CT-Brain"
  double level, window;   // centre and width, data values
  std::string_view description;
};

// Generated from Slicer's window/level presets file by scripts/gen-preset-tables.
std::span<const WindowPresetData> window_preset_table();

}  // namespace detail

// The presets' names as scene files spell them: lower case with hyphens ("ct-brain").
std::vector<std::string> window_preset_names();

// (centre, width) of the preset called `name` (matched like find_volume_preset); nullopt for an
// unknown name.
std::optional<glm::dvec2> find_window_preset(std::string_view name);

}  // namespace imx
