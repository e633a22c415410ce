#include "io/tiff/imagej_description.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx::detail {

namespace {

// ImageJ writes non-ASCII characters of its unit as Java escapes: "\u00B5m" is "µm".
std::string unescape(std::string_view s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\\' && i + 5 < s.size() && s[i + 1] == 'u') {
      char* end = nullptr;
      const std::string hex(s.substr(i + 2, 4));
      const unsigned long code = std::strtoul(hex.c_str(), &end, 16);
      if (end == hex.c_str() + 4) {
        if (code < 0x80) {
          out += static_cast<char>(code);
        } else if (code < 0x800) {
          out += static_cast<char>(0xC0 | (code >> 6));
          out += static_cast<char>(0x80 | (code & 0x3F));
        } else {
          out += static_cast<char>(0xE0 | (code >> 12));
          out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
          out += static_cast<char>(0x80 | (code & 0x3F));
        }
        i += 5;
        continue;
      }
    }
    out += s[i];
  }
  return out;
}

}  // namespace

bool is_imagej_description(std::string_view description) {
  return description.starts_with("ImageJ=");
}

ImageJDescription parse_imagej_description(std::string_view description, const std::string& what) {
  ImageJDescription d;
  const auto count = [&](std::string_view key, const std::string& value) {
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(value.c_str(), &end, 10);
    if (end == value.c_str() || *end != '\0' || errno != 0 || v < 1 || v >= (int64_t{1} << 31))
      throw Error(
          fmt::format("{}: ImageJ description: {}={} is not a positive integer", what, key, value));
    return static_cast<int64_t>(v);
  };
  size_t at = 0;
  while (at < description.size()) {
    size_t end = description.find('\n', at);
    if (end == std::string_view::npos) end = description.size();
    const std::string_view line = description.substr(at, end - at);
    at = end + 1;
    const size_t eq = line.find('=');
    if (eq == std::string_view::npos) continue;
    const std::string_view key = line.substr(0, eq);
    std::string value(line.substr(eq + 1));
    while (!value.empty() && (value.back() == '\r' || value.back() == ' ')) value.pop_back();
    if (key == "images") d.images = count(key, value);
    if (key == "channels") d.channels = count(key, value);
    if (key == "slices") d.slices = count(key, value);
    if (key == "frames") d.frames = count(key, value);
    if (key == "unit") d.unit = unescape(value);
    if (key == "spacing") {
      char* stop = nullptr;
      const double v = std::strtod(value.c_str(), &stop);
      if (stop == value.c_str() || *stop != '\0' || !std::isfinite(v) || v <= 0)
        throw Error(fmt::format("{}: ImageJ description: spacing={} is not a positive number", what,
                                value));
      d.spacing = v;
    }
  }
  return d;
}

}  // namespace imx::detail
