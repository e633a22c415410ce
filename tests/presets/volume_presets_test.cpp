#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/colour.hpp"
#include "presets/slicer_volume_property.hpp"
#include "presets/volume_presets.hpp"
#include "shared_data.hpp"
#include "volume/tf_lut.hpp"

namespace imx {
namespace {

// Each <VolumeProperty .../> element of Slicer's presets file as its attributes (a reader written
// apart from the generator script).
std::vector<std::map<std::string, std::string>> read_slicer_presets_xml(
    const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::vector<std::map<std::string, std::string>> out;
  for (size_t at = s.find("<VolumeProperty"); at != std::string::npos;
       at = s.find("<VolumeProperty", at + 1)) {
    const size_t end = s.find("/>", at);
    std::map<std::string, std::string> attributes;
    size_t i = at + std::string("<VolumeProperty").size();
    while (true) {
      const size_t eq = s.find("=\"", i);
      if (eq == std::string::npos || eq > end) break;
      size_t key_start = s.rfind(' ', eq) + 1;
      const size_t close = s.find('"', eq + 2);
      attributes[s.substr(key_start, eq - key_start)] = s.substr(eq + 2, close - eq - 2);
      i = close + 1;
    }
    out.push_back(attributes);
  }
  return out;
}

// "N v1 ... vN" as its N numbers.
std::vector<double> slicer_numbers(const std::string& text) {
  std::istringstream in(text);
  size_t n = 0;
  in >> n;
  std::vector<double> out;
  std::string token;
  while (in >> token) out.push_back(std::strtod(token.c_str(), nullptr));
  EXPECT_EQ(out.size(), n) << text;
  return out;
}

// A Slicer function (groups of `stride` numbers: x then values) at x, written apart from
// the library: linear between points, constant beyond the ends, a later point at the same x
// replacing an earlier one (identical in every preset that repeats an x).
double slicer_at(const std::vector<double>& f, size_t stride, size_t component, double x) {
  const size_t n = f.size() / stride;
  auto xs = [&](size_t i) { return f[i * stride]; };
  auto ys = [&](size_t i) { return f[i * stride + component]; };
  if (x <= xs(0)) {
    size_t last = 0;
    while (last + 1 < n && xs(last + 1) == xs(0)) ++last;
    return ys(last);
  }
  if (x >= xs(n - 1)) return ys(n - 1);
  for (size_t i = 0; i + 1 < n; ++i)
    if (x >= xs(i) && x < xs(i + 1)) {
      if (x == xs(i)) {
        size_t last = i;
        while (last + 1 < n && xs(last + 1) == x) ++last;
        return ys(last);
      }
      return ys(i) + (x - xs(i)) / (xs(i + 1) - xs(i)) * (ys(i + 1) - ys(i));
    }
  return ys(n - 1);
}

TEST(VolumePresets, NamesAreTheSceneSpellingOfEverySlicerPreset) {
  std::vector<std::string> names = volume_preset_names();
  EXPECT_EQ(names.size(), 31u);
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  for (const char* want : {"ct-bone", "ct-soft-tissue", "ct-muscle", "ct-lung", "ct-aaa",
                           "ct-cardiac", "mr-default", "mr-angio", "mr-t2-brain", "uct-skull"})
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
  for (const std::string& n : names)
    EXPECT_EQ(n.find_first_of("ABCDEFGHIJKLMNOPQRSTUVWXYZ _"), std::string::npos) << n;
}

TEST(VolumePresets, SlicerNamesFindTheSamePresetIgnoringCase) {
  ASSERT_TRUE(find_volume_preset("ct-bone"));
  EXPECT_EQ(find_volume_preset("ct-bone")->name, "CT-Bone");
  EXPECT_EQ(find_volume_preset("CT-Bone")->name, "CT-Bone");
  EXPECT_EQ(find_volume_preset("ct_BONE")->name, "CT-Bone");
  EXPECT_EQ(find_volume_preset("MR-T2-Brain")->name, "MR-T2-Brain");
  EXPECT_FALSE(find_volume_preset("ct-bones-extra"));
  EXPECT_FALSE(find_volume_preset(""));
}

// CT-Bone's numbers as the presets file has them: checked without the shared data folder. Its
// colours are display colours, decoded at each merged point (docs/colour.md); opacity as given.
TEST(VolumePresets, CtBoneMergesToSlicersPointsExactly) {
  SlicerVolumeProperty p = *find_volume_preset("ct-bone");
  TransferFunction tf = to_transfer_function(p);
  EXPECT_EQ(tf.unit_distance, 1.0);
  ASSERT_EQ(tf.points.size(), 4u);  // both functions have their points at the same values
  const double values[] = {-3024, -16.4458, 641.385, 3071};
  const float rgba[4][4] = {{0, 0, 0, 0},
                            {0.729412f, 0.254902f, 0.301961f, 0},
                            {0.905882f, 0.815686f, 0.552941f, 0.715686f},
                            {1, 1, 1, 0.705882f}};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(tf.points[i].value, values[i]);
    for (int c = 0; c < 3; ++c)
      EXPECT_FLOAT_EQ(tf.points[i].rgba[c], srgb_decode(rgba[i][c])) << i << c;
    EXPECT_FLOAT_EQ(tf.points[i].rgba.a, rgba[i][3]) << i;
  }
  // Linear between (in linear light): half way from -16.4458 to 641.385.
  glm::vec4 mid = evaluate_transfer_function(tf, 0.5 * (-16.4458 + 641.385));
  EXPECT_NEAR(mid.a, 0.5 * 0.715686, 1e-6);
  EXPECT_NEAR(mid.r, 0.5 * (srgb_decode(0.729412f) + srgb_decode(0.905882f)), 1e-6);
  Shading s = to_shading(p);
  EXPECT_TRUE(s.enabled);
  EXPECT_FLOAT_EQ(s.ambient, 0.1f);
  EXPECT_FLOAT_EQ(s.diffuse, 0.9f);
  EXPECT_FLOAT_EQ(s.specular, 0.2f);
  EXPECT_FLOAT_EQ(s.shininess, 10.0f);
  ASSERT_TRUE(p.effective_range);
  EXPECT_EQ(*p.effective_range, glm::dvec2(-16.4458, 641.385));
  EXPECT_FALSE(to_shading(*find_volume_preset("ct-soft-tissue")).enabled);
}

// Where opacity and colour have points at different values, the merge has a point at each.
TEST(VolumePresets, ColourAndOpacityAtDifferentValuesMergeAtTheirUnion) {
  SlicerVolumeProperty p = *find_volume_preset("ct-bones");  // colour has 5 points, opacity 4
  TransferFunction tf = to_transfer_function(p);
  std::set<double> want;
  for (const glm::dvec2& q : p.scalar_opacity) want.insert(q.x);
  for (const glm::dvec4& q : p.color) want.insert(q.x);
  ASSERT_EQ(tf.points.size(), want.size());
  size_t i = 0;
  for (double v : want) EXPECT_EQ(tf.points[i++].value, v);
  // -488 is a colour point only: its opacity is the opacity function's there (0, below 152.19).
  glm::vec4 at = evaluate_transfer_function(tf, -488.0);
  EXPECT_FLOAT_EQ(at.r, srgb_decode(0.3f));
  EXPECT_FLOAT_EQ(at.g, 1.0f);
  EXPECT_FLOAT_EQ(at.a, 0.0f);
  // 953 lies beyond the opacity's last point (952, 0.2): opacity stays 0.2.
  EXPECT_FLOAT_EQ(evaluate_transfer_function(tf, 953.0).a, 0.2f);
}

TEST(VolumePresets, OnlyUctSkullHasAGradientOpacityThatMatters) {
  std::vector<std::string> non_trivial;
  for (const std::string& n : volume_preset_names())
    if (!gradient_opacity_is_trivial(*find_volume_preset(n))) non_trivial.push_back(n);
  EXPECT_EQ(non_trivial, std::vector<std::string>{"uct-skull"});
}

// Every preset of Slicer's file: the same set of names, shading, and merged points that give
// Slicer's opacity at every original control point and half way between neighbours, and its
// colour, decoded, at every control point; half way, the decoded neighbours' mean (colours
// blend in linear light between points, docs/colour.md).
TEST(VolumePresets, EveryPresetInSlicersFileEvaluatesToItsFunctions) {
  const auto file = test::shared_data("slicer-volume-rendering-presets.xml");
  SKIP_WITHOUT_SHARED_DATA(file);
  const auto presets = read_slicer_presets_xml(file);
  ASSERT_EQ(presets.size(), volume_preset_names().size());
  for (const auto& attributes : presets) {
    const std::string name = attributes.at("name");
    SCOPED_TRACE(name);
    std::optional<SlicerVolumeProperty> p = find_volume_preset(name);
    ASSERT_TRUE(p);
    EXPECT_EQ(p->shade, attributes.at("shade") == "1");
    EXPECT_EQ(p->ambient, std::stod(attributes.at("ambient")));
    EXPECT_EQ(p->diffuse, std::stod(attributes.at("diffuse")));
    EXPECT_EQ(p->specular, std::stod(attributes.at("specular")));
    EXPECT_EQ(p->specular_power, std::stod(attributes.at("specularPower")));
    const std::vector<double> opacity = slicer_numbers(attributes.at("scalarOpacity"));
    const std::vector<double> color = slicer_numbers(attributes.at("colorTransfer"));
    const TransferFunction tf = to_transfer_function(*p);
    std::vector<double> xs;
    for (size_t i = 0; i < opacity.size(); i += 2) xs.push_back(opacity[i]);
    for (size_t i = 0; i < color.size(); i += 4) xs.push_back(color[i]);
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    EXPECT_EQ(tf.points.size(), xs.size());
    // Probes and the points whose colours the TF blends there (equal for a point or an end).
    std::vector<std::array<double, 3>> probes;
    for (double x : xs) probes.push_back({x, x, x});
    for (size_t i = 0; i + 1 < xs.size(); ++i)
      probes.push_back({0.5 * (xs[i] + xs[i + 1]), xs[i], xs[i + 1]});
    probes.push_back({xs.front() - 100.0, xs.front(), xs.front()});
    probes.push_back({xs.back() + 100.0, xs.back(), xs.back()});
    for (const auto& [x, left, right] : probes) {
      glm::vec4 got = evaluate_transfer_function(tf, x);
      // float colours and interpolation weights: a few float ulps of a value in [0, 1]
      EXPECT_NEAR(got.a, slicer_at(opacity, 2, 1, x), 2e-6) << "opacity at " << x;
      for (int c = 0; c < 3; ++c) {
        const auto decoded = [&](double at) {
          return srgb_decode(
              static_cast<float>(slicer_at(color, 4, 1 + static_cast<size_t>(c), at)));
        };
        EXPECT_NEAR(got[c], 0.5 * (decoded(left) + decoded(right)), 2e-6)
            << "colour " << c << " at " << x;
      }
    }
  }
}

}  // namespace
}  // namespace imx
