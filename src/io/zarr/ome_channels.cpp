#include "io/zarr/ome_channels.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx::detail {

namespace {

using nlohmann::json;

glm::vec3 parse_colour(const json& v, const std::string& field, const std::string& what) {
  const std::string s = v.is_string() ? v.get<std::string>() : std::string();
  glm::vec3 c(0.0f);
  bool ok = s.size() == 6;
  for (size_t k = 0; ok && k < 6; ++k) {
    const char h = s[k];
    const int digit = h >= '0' && h <= '9'   ? h - '0'
                      : h >= 'a' && h <= 'f' ? h - 'a' + 10
                      : h >= 'A' && h <= 'F' ? h - 'A' + 10
                                             : -1;
    ok = digit >= 0;
    c[static_cast<int>(k / 2)] += static_cast<float>(digit * (k % 2 ? 1 : 16));
  }
  if (!ok)
    throw Error(fmt::format("{}: field '{}' {} is not a colour (six hex digits, RRGGBB)", what,
                            field, v.dump().substr(0, 40)));
  return c / 255.0f;
}

std::optional<double> number(const json& window, const char* key, const std::string& field,
                             const std::string& what) {
  if (!window.contains(key)) return std::nullopt;
  const json& v = window[key];
  if (!v.is_number() || !std::isfinite(v.get<double>()))
    throw Error(fmt::format("{}: field '{}.{}' {} is not a finite number", what, field, key,
                            v.dump().substr(0, 40)));
  return v.get<double>();
}

}  // namespace

std::vector<OmeChannel> parse_ome_channels(const json& omero, int count, const std::string& what) {
  std::vector<OmeChannel> channels(static_cast<size_t>(count));
  for (int c = 0; c < count; ++c)
    channels[static_cast<size_t>(c)].label = fmt::format("channel {}", c);
  if (omero.is_null()) return channels;
  if (!omero.is_object() || !omero.contains("channels")) return channels;
  const json& list = omero["channels"];
  if (!list.is_array()) throw Error(fmt::format("{}: field 'omero.channels' is not a list", what));
  // Writers list channels for images without a channel axis too: entries past `count` describe
  // nothing this image holds, so they are left unread rather than refusing the image.
  for (size_t c = 0; c < std::min(list.size(), channels.size()); ++c) {
    const json& o = list[c];
    const std::string field = fmt::format("omero.channels[{}]", c);
    if (!o.is_object()) throw Error(fmt::format("{}: field '{}' is not an object", what, field));
    OmeChannel& ch = channels[c];
    ch.listed = true;
    if (o.contains("label") && o["label"].is_string() && !o["label"].get<std::string>().empty())
      ch.label = o["label"].get<std::string>();
    if (o.contains("color")) ch.srgb = parse_colour(o["color"], field + ".color", what);
    if (o.contains("active")) {
      if (!o["active"].is_boolean())
        throw Error(fmt::format("{}: field '{}.active' is not true or false", what, field));
      ch.active = o["active"].get<bool>();
    }
    if (o.contains("window")) {
      const json& w = o["window"];
      const std::string wf = field + ".window";
      if (!w.is_object()) throw Error(fmt::format("{}: field '{}' is not an object", what, wf));
      const auto start = number(w, "start", wf, what), end = number(w, "end", wf, what);
      const auto lo = number(w, "min", wf, what), hi = number(w, "max", wf, what);
      if (start && end) {
        if (!(*start < *end))
          throw Error(
              fmt::format("{}: field '{}': start {} is not below end {}", what, wf, *start, *end));
        ch.window = glm::dvec2(*start, *end);
      }
      if (lo && hi) ch.range = glm::dvec2(*lo, *hi);
    }
  }
  return channels;
}

}  // namespace imx::detail
