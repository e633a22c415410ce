// ImageJ's ImageDescription ("ImageJ=1.53t\nimages=24\nchannels=2\nslices=3\nframes=4\n
// spacing=2.5\nunit=micron\n..."): a hyperstack's shape and its z spacing and unit.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace imx::detail {

struct ImageJDescription {
  int64_t images = 0, channels = 1, slices = 0, frames = 1;  // slices 0: not given
  std::optional<double> spacing;                             // z step, in `unit`
  std::string unit;  // "micron", "µm" (ImageJ's "\u00B5m" decoded), "" when none
};

// Whether `description` is ImageJ's (its first line starts "ImageJ=").
bool is_imagej_description(std::string_view description);

// The fields above. Throws imx::Error naming `what` and the key for a count that is not a
// positive integer below 2^31 or a spacing that is not a positive number.
ImageJDescription parse_imagej_description(std::string_view description, const std::string& what);

}  // namespace imx::detail
