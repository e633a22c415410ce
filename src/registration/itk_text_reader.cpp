// ITK's text transform files (.tfm, .txt) as 3D Slicer, ANTs and ITK itself write them.
#include <fmt/format.h>

#include "intermix/error.hpp"
#include "registration/transform_readers.hpp"

namespace imx::detail {
namespace {

bool starts_with(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

bool is_composite(const std::string& type) {
  return type == "CompositeTransform_double_3" || type == "CompositeTransform_float_3";
}

std::vector<double> numbers_after(std::string_view line, size_t colon, const std::string& what,
                                  const std::string& field) {
  std::vector<double> out;
  for (std::string_view w : words(line.substr(colon + 1)))
    out.push_back(parse_number(w, what, field));
  return out;
}

}  // namespace

glm::dmat4 read_itk_text(std::string_view text, const std::string& what) {
  const std::vector<std::string_view> lines = text_lines(text, what);
  size_t first = 0;
  while (first < lines.size() && words(lines[first]).empty()) ++first;
  if (first == lines.size() || !starts_with(lines[first], "#Insight Transform File"))
    throw Error(
        fmt::format("{}: not an ITK transform file (it must start with \"#Insight "
                    "Transform File V1.0\")",
                    what));
  std::vector<ItkTransform> transforms;
  std::vector<bool> has_parameters, has_fixed;
  for (size_t i = first + 1; i < lines.size(); ++i) {
    std::string_view line = lines[i];
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    if (line.empty() || line.front() == '#') continue;
    const size_t colon = line.find(':');
    const std::string key(line.substr(0, colon == std::string_view::npos ? line.size() : colon));
    if (colon == std::string_view::npos)
      throw Error(fmt::format("{}: line {}: expected \"Key: value\", got '{}'", what, i + 1,
                              std::string(line.substr(0, 60))));
    if (key == "Transform") {
      std::vector<std::string_view> w = words(line.substr(colon + 1));
      if (w.size() != 1)
        throw Error(fmt::format("{}: line {}: expected one transform type after \"Transform:\"",
                                what, i + 1));
      transforms.push_back({std::string(w[0]), {}, {}});
      has_parameters.push_back(false);
      has_fixed.push_back(false);
      continue;
    }
    if (transforms.empty())
      throw Error(fmt::format("{}: line {}: {} before any \"Transform:\" line", what, i + 1, key));
    const std::string field = fmt::format("line {} ({})", i + 1, key);
    if (key == "Parameters") {
      transforms.back().parameters = numbers_after(line, colon, what, field);
      has_parameters.back() = true;
    } else if (key == "FixedParameters") {
      transforms.back().fixed = numbers_after(line, colon, what, field);
      has_fixed.back() = true;
    } else {
      throw Error(
          fmt::format("{}: line {}: unknown key '{}' (an ITK transform file has "
                      "Transform, Parameters and FixedParameters)",
                      what, i + 1, key.substr(0, 40)));
    }
  }
  if (transforms.empty()) throw Error(fmt::format("{}: holds no transform (truncated?)", what));
  const bool composite = is_composite(transforms.front().type);
  const size_t begin = composite ? 1 : 0;
  if (composite && (!transforms.front().parameters.empty() || !transforms.front().fixed.empty()))
    throw Error(fmt::format("{}: the CompositeTransform has parameters of its own", what));
  if (!composite && transforms.size() > 1)
    throw Error(
        fmt::format("{}: holds {} transforms outside a CompositeTransform; which one "
                    "places the image is not said (give one, or a composite)",
                    what, transforms.size()));
  if (transforms.size() == begin)
    throw Error(fmt::format("{}: the CompositeTransform holds no transform", what));
  glm::dmat4 m(1.0);
  for (size_t k = begin; k < transforms.size(); ++k) {
    if (is_composite(transforms[k].type))
      throw Error(fmt::format("{}: transform {} is a CompositeTransform inside another", what, k));
    if (!has_parameters[k] || !has_fixed[k])
      throw Error(fmt::format("{}: transform {} ({}) has no {} line (truncated file?)", what, k,
                              transforms[k].type.substr(0, 80),
                              has_parameters[k] ? "FixedParameters" : "Parameters"));
    // A composite applies its last transform first: T = T_1 o T_2 o ... o T_n.
    m = m * itk_fixed_to_moving(transforms[k], what);
  }
  return m;
}

}  // namespace imx::detail
