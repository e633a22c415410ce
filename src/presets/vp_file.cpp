#include "presets/vp_file.hpp"

#include <charconv>
#include <cmath>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "presets/text_file.hpp"

namespace imx {
namespace {

constexpr size_t kMaxVpBytes = 16u << 20;

// One line of the file and what it holds, for messages.
struct Line {
  std::string_view text;
  int number = 0;  // 1-based, counting blank lines too
  const char* field = "";
};

class VpParser {
 public:
  explicit VpParser(const std::filesystem::path& file) : file_(file) {}

  [[noreturn]] void fail(const Line& line, const std::string& message) const {
    throw Error(
        fmt::format("{}: line {} ({}): {}", file_.string(), line.number, line.field, message));
  }

  std::vector<std::string_view> tokens(const Line& line) const {
    std::vector<std::string_view> out;
    size_t i = 0;
    const std::string_view t = line.text;
    while (i < t.size()) {
      while (i < t.size() && (t[i] == ' ' || t[i] == '\t' || t[i] == '\r')) ++i;
      size_t j = i;
      while (j < t.size() && t[j] != ' ' && t[j] != '\t' && t[j] != '\r') ++j;
      if (j > i) out.push_back(t.substr(i, j - i));
      i = j;
    }
    return out;
  }

  double number(const Line& line, std::string_view token) const {
    double v = 0.0;
    const char* end = token.data() + token.size();
    auto [ptr, ec] = std::from_chars(token.data(), end, v);
    if (ec != std::errc() || ptr != end) fail(line, fmt::format("'{}' is not a number", token));
    if (!std::isfinite(v)) fail(line, fmt::format("'{}' is not finite", token));
    return v;
  }

  // A line holding one number in [lo, hi].
  double scalar(const Line& line, double lo, double hi) const {
    std::vector<std::string_view> t = tokens(line);
    if (t.size() != 1) fail(line, fmt::format("expected one number, found {} fields", t.size()));
    double v = number(line, t[0]);
    if (!(v >= lo && v <= hi)) fail(line, fmt::format("{} is not in [{}, {}]", v, lo, hi));
    return v;
  }

  // A function line "N v0 v1 ...": N numbers in groups of `stride`, x sorted, the rest in [0, 1].
  std::vector<double> function(const Line& line, size_t stride) const {
    std::vector<std::string_view> t = tokens(line);
    if (t.empty()) fail(line, "is empty");
    double count = number(line, t[0]);
    const double most = static_cast<double>(kMaxVpPoints * stride);
    if (!(count >= static_cast<double>(stride)) || count != std::floor(count))
      fail(line, fmt::format("count {} is not a whole number of at least {}", t[0], stride));
    if (count > most)
      fail(line, fmt::format("count {} is more than {} points allow", t[0], kMaxVpPoints));
    const auto n = static_cast<size_t>(count);
    if (n % stride != 0)
      fail(line, fmt::format("count {} is not a multiple of {} (values per point)", n, stride));
    if (n != t.size() - 1)
      fail(line,
           fmt::format("count {} does not match the {} numbers that follow it", n, t.size() - 1));
    std::vector<double> out(n);
    for (size_t i = 0; i < n; ++i) {
      out[i] = number(line, t[i + 1]);
      if (i % stride == 0) {
        if (i >= stride && out[i] < out[i - stride])
          fail(line, fmt::format("point {} at {} is below the previous point's {} (points must "
                                 "be sorted)",
                                 i / stride, out[i], out[i - stride]));
      } else if (!(out[i] >= 0.0 && out[i] <= 1.0)) {
        fail(line, fmt::format("point {}: {} is not in [0, 1]", i / stride, out[i]));
      }
    }
    return out;
  }

 private:
  const std::filesystem::path& file_;
};

}  // namespace

SlicerVolumeProperty read_vp_file(const std::filesystem::path& file) {
  const std::string text = read_text_file(file, kMaxVpBytes);
  static constexpr const char* kFields[] = {
      "interpolation",  "shade",          "ambient",          "diffuse", "specular",
      "specular power", "scalar opacity", "gradient opacity", "colour"};
  std::vector<Line> lines;
  int number = 0;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    ++number;
    std::string_view line(text.data() + start, end - start);
    if (line.find_first_not_of(" \t\r") != std::string_view::npos) {
      if (lines.size() == std::size(kFields))
        throw Error(fmt::format("{}: line {}: more than the {} lines of a volume property file",
                                file.string(), number, std::size(kFields)));
      lines.push_back({line, number, kFields[lines.size()]});
    }
    start = end + 1;
  }
  if (lines.size() < std::size(kFields))
    throw Error(fmt::format("{}: has {} lines, a volume property file has {} (the {} is missing)",
                            file.string(), lines.size(), std::size(kFields),
                            kFields[lines.size()]));
  VpParser p(file);
  SlicerVolumeProperty vp;
  vp.name = file.stem().string();
  p.scalar(lines[0], 0.0, 2.0);  // nearest, linear or cubic: intermix samples linearly
  vp.shade = p.scalar(lines[1], 0.0, 1.0) != 0.0;
  vp.ambient = p.scalar(lines[2], 0.0, 1000.0);
  vp.diffuse = p.scalar(lines[3], 0.0, 1000.0);
  vp.specular = p.scalar(lines[4], 0.0, 1000.0);
  vp.specular_power = p.scalar(lines[5], 0.0, 1000.0);
  vp.scalar_opacity = slicer_opacity_points(p.function(lines[6], 2));
  vp.gradient_opacity = slicer_opacity_points(p.function(lines[7], 2));
  vp.color = slicer_color_points(p.function(lines[8], 4));
  return vp;
}

}  // namespace imx
