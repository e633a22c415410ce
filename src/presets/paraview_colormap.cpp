#include "presets/paraview_colormap.hpp"

#include <cmath>
#include <exception>

#include <fmt/format.h>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
#include <nlohmann/json.hpp>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "presets/text_file.hpp"
#include "presets/tf_merge.hpp"

namespace imx {
namespace {

constexpr size_t kMaxParaviewBytes = 64u << 20;  // ParaView's own preset list is a few MB

using Json = nlohmann::json;

struct MapReader {
  const std::filesystem::path& file;
  std::string where;  // "[3] (\"Cool to Warm\")"

  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw Error(fmt::format("{}: {}.{}: {}", file.string(), where, field, message));
  }

  // `field` as numbers in groups of `stride`: x non-decreasing, the next `checked` of each group
  // in [0, 1].
  std::vector<double> numbers(const Json& map, const char* field, size_t stride,
                              size_t checked) const {
    const Json& list = map.at(field);
    if (!list.is_array()) fail(field, "expected an array of numbers, got " + list.dump());
    if (list.empty() || list.size() % stride != 0)
      fail(field,
           fmt::format("has {} numbers, expected a non-zero multiple of {}", list.size(), stride));
    if (list.size() / stride > kMaxParaviewPoints)
      fail(field,
           fmt::format("has {} points, more than {}", list.size() / stride, kMaxParaviewPoints));
    std::vector<double> out(list.size());
    for (size_t i = 0; i < list.size(); ++i) {
      if (!list[i].is_number())
        fail(fmt::format("{}[{}]", field, i), "expected a number, got " + list[i].dump());
      out[i] = list[i].get<double>();
      if (!std::isfinite(out[i])) fail(fmt::format("{}[{}]", field, i), "is not finite");
      size_t k = i % stride;
      if (k == 0 && i >= stride && out[i] < out[i - stride])
        fail(fmt::format("{}[{}]", field, i),
             fmt::format("value {} is below the previous point's {} (points must be sorted)",
                         out[i], out[i - stride]));
      if (k >= 1 && k <= checked && !(out[i] >= 0.0 && out[i] <= 1.0))
        fail(fmt::format("{}[{}]", field, i), fmt::format("{} is not in [0, 1]", out[i]));
    }
    return out;
  }
};

std::string name_of(const Json& map) {
  auto it = map.find("Name");
  return it != map.end() && it->is_string() ? it->get<std::string>() : std::string();
}

std::string list_names(const Json& maps) {
  std::string out;
  for (const Json& m : maps) out += (out.empty() ? "'" : ", '") + name_of(m) + "'";
  return out;
}

}  // namespace

ParaviewColormap read_paraview_colormap(const std::filesystem::path& file,
                                        const std::string& name) {
  const std::string text = read_text_file(file, kMaxParaviewBytes);
  Json root;
  try {
    root = Json::parse(text);
  } catch (const std::exception& e) {
    std::string what = e.what();
    if (auto at = what.find("] "); at != std::string::npos) what = what.substr(at + 2);
    throw Error(fmt::format("{}: not valid JSON: {}", file.string(), what));
  }
  if (root.is_object()) root = Json::array({root});
  if (!root.is_array() || root.empty())
    throw Error(fmt::format("{}: expected an array of ParaView colour maps", file.string()));
  size_t index = root.size();
  for (size_t i = 0; i < root.size(); ++i) {
    if (!root[i].is_object())
      throw Error(fmt::format("{}: [{}]: expected a colour map object, got {}", file.string(), i,
                              root[i].dump().substr(0, 60)));
    if (!name.empty() && name_of(root[i]) == name) {
      index = i;
      break;
    }
  }
  if (name.empty() && root.size() == 1) index = 0;
  if (index == root.size()) {
    if (name.empty())
      throw Error(fmt::format("{}: holds {} colour maps; choose one with \"name\": {}",
                              file.string(), root.size(), list_names(root)));
    throw Error(fmt::format("{}: has no colour map named '{}'; it has {}", file.string(), name,
                            list_names(root)));
  }
  const Json& map = root[index];
  ParaviewColormap out;
  out.name = name_of(map);
  MapReader r{file, fmt::format("[{}]", index)};
  if (!out.name.empty()) r.where += fmt::format(" ('{}')", out.name);
  if (!map.contains("RGBPoints"))
    r.fail("RGBPoints", "is missing (an indexed or categorical map has no RGBPoints)");
  std::vector<double> rgb = r.numbers(map, "RGBPoints", 4, 3);
  std::vector<glm::dvec4> color;
  for (size_t i = 0; i < rgb.size(); i += 4)
    color.emplace_back(rgb[i], rgb[i + 1], rgb[i + 2], rgb[i + 3]);
  std::vector<glm::dvec2> opacity;
  if (map.contains("Points")) {
    std::vector<double> a = r.numbers(map, "Points", 4, 1);
    bool curved = false;
    for (size_t i = 0; i < a.size(); i += 4) {
      opacity.emplace_back(a[i], a[i + 1]);
      curved = curved || a[i + 2] != 0.5 || a[i + 3] != 0.0;
    }
    if (curved)
      out.notes.push_back(
          fmt::format("{}: opacity midpoints and sharpness other than 0.5 and 0 are read as linear",
                      file.string()));
  } else {
    opacity = {{color.front().x, 0.0}, {color.back().x, 1.0}};
    out.notes.push_back(fmt::format(
        "{}: '{}' has no opacity \"Points\": opacity ramps linearly from 0 at {} to 1 at {}",
        file.string(), out.name, color.front().x, color.back().x));
  }
  if (auto cs = map.find("ColorSpace");
      cs != map.end() && cs->is_string() && cs->get<std::string>() != "RGB")
    out.notes.push_back(fmt::format("{}: '{}' colours are interpolated in RGB, not {}",
                                    file.string(), out.name, cs->get<std::string>()));
  out.transfer_function = merge_opacity_and_color(opacity, color);
  // ParaView's colours are display colours, as ParaView shows them at each merged point.
  for (TfPoint& point : out.transfer_function.points) point.rgba = display_to_linear(point.rgba);
  return out;
}

}  // namespace imx
