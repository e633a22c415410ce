// The channels of an OME-Zarr image as its "omero" metadata gives them: each one's name, colour,
// display window and whether it is shown (OME-NGFF 0.4 .zattrs "omero", 0.5 "ome"."omero").
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

namespace imx::detail {

struct OmeChannel {
  std::string label;                 // "channel K" when the file names none
  glm::vec3 srgb{1.0f};              // "color" RRGGBB, as written (sRGB-encoded); white when none
  std::optional<glm::dvec2> window;  // window.start, window.end (the display range)
  std::optional<glm::dvec2> range;   // window.min, window.max (the data's range)
  bool active = true;
  bool listed = false;  // omero.channels has an entry for it
};

// `count` channels: what `omero` (null when absent) says of each, defaults for the rest (entries
// past `count` are left unread). Refuses (imx::Error naming `what` and the field) a colour that
// is not six hex digits and a window that is not numbers with start below end.
std::vector<OmeChannel> parse_ome_channels(const nlohmann::json& omero, int count,
                                           const std::string& what);

}  // namespace imx::detail
