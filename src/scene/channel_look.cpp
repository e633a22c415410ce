#include "scene/channel_look.hpp"

#include <fmt/format.h>

#include "core/colour.hpp"

namespace imx {

namespace {

// The opacity at the window's end: bright voxels show through one another, as with the grey
// ramp of automatic_look, so several channels of one grid stay visible together.
constexpr double kTopOpacity = 0.5;

}  // namespace

glm::dvec2 channel_window(const detail::OmeChannel& channel, const VolumeData& data,
                          const char** from) {
  const char* which = "its window";
  glm::dvec2 window;
  if (channel.window) {
    window = *channel.window;
  } else if (channel.range && channel.range->y > channel.range->x) {
    window = *channel.range, which = "its range (no window)";
  } else {
    const auto [lo, hi] = data.range();
    window = {lo, hi > lo ? hi : lo + 1.0}, which = "the voxels' range";
  }
  if (from) *from = which;
  return window;
}

AutomaticLook channel_look(const detail::OmeChannel& channel, const VolumeData& data) {
  const char* from = nullptr;
  const glm::dvec2 window = channel_window(channel, data, &from);
  // The channel's display colour as given: the scene loader decodes it like any point's.
  const glm::dvec3 c(channel.srgb);
  const nlohmann::json points =
      nlohmann::json::array({nlohmann::json::array({window.x, c.r, c.g, c.b, 0.0}),
                             nlohmann::json::array({window.y, c.r, c.g, c.b, kTopOpacity})});
  const auto hex = [](float v) { return static_cast<int>(v * 255.0f + 0.5f); };
  return {{{"points", points}},
          nullptr,
          fmt::format("OME channel '{}': colour {:02X}{:02X}{:02X} over {} {:g} to {:g}",
                      channel.label, hex(channel.srgb.r), hex(channel.srgb.g), hex(channel.srgb.b),
                      from, window.x, window.y)};
}

}  // namespace imx
