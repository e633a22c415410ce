#include "scene/channel_blend.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "scene/channel_look.hpp"

namespace imx {

VolumeData blend_channels(std::span<const VolumeData> volumes,
                          std::span<const detail::OmeChannel> looks, ChannelBlend blend,
                          const std::string& what) {
  if (volumes.empty() || volumes.size() != looks.size())
    throw Error(
        fmt::format("{}: {} channel grids for {} channels", what, volumes.size(), looks.size()));
  const VolumeData& first = volumes[0];
  const size_t count = first.voxel_count();
  std::vector<glm::vec3> linear(count, glm::vec3(0.0f));
  std::vector<float> scale(count, 0.0f);
  for (size_t c = 0; c < volumes.size(); ++c) {
    const VolumeData& v = volumes[c];
    if (v.dims != first.dims)
      throw Error(fmt::format("{}: channel {} is {}x{}x{}, channel 0 {}x{}x{}", what, c, v.dims.x,
                              v.dims.y, v.dims.z, first.dims.x, first.dims.y, first.dims.z));
    const glm::dvec2 w = channel_window(looks[c], v);
    const glm::vec3 colour = display_to_linear(glm::vec3(looks[c].srgb));
    std::visit(
        [&](const auto& voxels) {
          for (size_t i = 0; i < count; ++i) {
            const double x = static_cast<double>(voxels.data()[i]);
            // NaN (no data) adds nothing, as below the window.
            const float s = std::isnan(x)
                                ? 0.0f
                                : static_cast<float>(std::clamp((x - w.x) / (w.y - w.x), 0.0, 1.0));
            if (blend == ChannelBlend::add) {
              linear[i] += s * colour;
              scale[i] += s;
            } else {
              linear[i] = glm::max(linear[i], s * colour);
              scale[i] = std::max(scale[i], s);
            }
          }
        },
        v.voxels);
  }
  auto colours = std::make_shared<ColourVoxels>();
  colours->rgb.resize(3 * count);
  std::vector<uint8_t> scalar(count);
  const auto byte = [](float v) {
    return static_cast<uint8_t>(std::lround(255.0f * std::clamp(v, 0.0f, 1.0f)));
  };
  for (size_t i = 0; i < count; ++i) {
    for (int k = 0; k < 3; ++k)
      colours->rgb[3 * i + static_cast<size_t>(k)] = byte(srgb_encode(linear[i][k]));
    scalar[i] = byte(scale[i]);
  }
  VolumeData out;
  out.dims = first.dims;
  out.index_to_world = first.index_to_world;
  out.voxels = VoxelBuffer<uint8_t>(std::move(scalar));
  out.colours = std::move(colours);
  return out;
}

}  // namespace imx
