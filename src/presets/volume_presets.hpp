// 3D Slicer's volume-rendering presets (CT-Bone, MR-Default, ...), looked up by name.
#pragma once
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "presets/slicer_volume_property.hpp"

namespace imx {

namespace detail {

// One preset's numbers as Slicer's presets file spells them (flat x, y / x, r, g, b lists).
struct VolumePresetData {
  std::string_view name;  // Slicer's name, e.g. "CT-Bone"
  std::span<const double> scalar_opacity;
  std::span<const double> gradient_opacity;
  std::span<const double> color;
  bool shade;
  double ambient, diffuse, specular, specular_power;
  double range_lo, range_hi;  // effective range; lo >= hi where the file gives none
};

// Generated from Slicer's presets file by scripts/gen-preset-tables.
std::span<const VolumePresetData> volume_preset_table();

}  // namespace detail

// The presets' names as scene files spell them: lower case with hyphens ("ct-bone").
std::vector<std::string> volume_preset_names();

// The preset called `name`, matched ignoring case and treating '_' and ' ' as '-', so both
// "ct-bone" and Slicer's "CT-Bone" find it; nullopt for an unknown name.
std::optional<SlicerVolumeProperty> find_volume_preset(std::string_view name);

}  // namespace imx
