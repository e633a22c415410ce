// ParaView's colour-map files (JSON): an array of maps, each with "Name", "RGBPoints" and
// optionally opacity "Points".
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "intermix/scene.hpp"

namespace imx {

// The most points one function of a ParaView map may have.
inline constexpr size_t kMaxParaviewPoints = 65536;

struct ParaviewColormap {
  std::string name;
  TransferFunction transfer_function;  // colour and opacity merged, alphas per 1 mm
  std::vector<std::string> notes;      // what reading chose (an opacity ramp, RGB interpolation)
};

// The map called `name` in `file` (or its only map when `name` is empty). RGBPoints
// [x, r, g, b, ...] give the colour; "Points" [x, opacity, midpoint, sharpness, ...] the opacity,
// else a linear ramp from 0 to 1 over the colour points' range. Colours are interpolated in RGB
// whatever "ColorSpace" says, and midpoint / sharpness other than 0.5 / 0 are read as linear;
// both are said in `notes`. Throws imx::Error naming the file and the field: not JSON, no or
// several maps, a missing or malformed list, a wrong count, unsorted or non-finite values,
// values out of [0, 1], or more than kMaxParaviewPoints points.
ParaviewColormap read_paraview_colormap(const std::filesystem::path& file, const std::string& name);

}  // namespace imx
