#include <gtest/gtest.h>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "expect_error.hpp"
#include "presets/volume_presets.hpp"
#include "presets/vp_file.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"
#include "volume/tf_lut.hpp"

namespace imx {
namespace {

using test::error_of;

// A .vp file's text from its nine lines.
std::string vp(const std::string& opacity, const std::string& color,
               const std::string& gradient = "4 0 1 255 1") {
  return fmt::format("1\n1\n0.1\n0.9\n0.2\n10\n{}\n{}\n{}\n", opacity, gradient, color);
}

// The text of a .vp file holding one of the built-in presets.
std::string vp_of(const detail::VolumePresetData& d) {
  auto flat = [](std::span<const double> v) {
    std::string s = std::to_string(v.size());
    for (double x : v) s += fmt::format(" {}", x);
    return s;
  };
  return fmt::format("1\n{}\n{}\n{}\n{}\n{}\n{}\n{}\n{}\n", d.shade ? 1 : 0, d.ambient, d.diffuse,
                     d.specular, d.specular_power, flat(d.scalar_opacity), flat(d.gradient_opacity),
                     flat(d.color));
}

TEST(VpFile, SlicersSampleFileReads) {
  const auto file = test::shared_data("slicer-VolumeProperty.vp");
  SKIP_WITHOUT_SHARED_DATA(file);
  SlicerVolumeProperty p = read_vp_file(file);
  EXPECT_TRUE(p.shade);
  EXPECT_EQ(p.ambient, 0.42);
  EXPECT_EQ(p.diffuse, 0.44);
  EXPECT_EQ(p.specular, 0.46);
  EXPECT_EQ(p.specular_power, 38.5);
  ASSERT_EQ(p.scalar_opacity.size(), 4u);
  EXPECT_EQ(p.scalar_opacity[2], glm::dvec2(103, 1));
  ASSERT_EQ(p.color.size(), 7u);
  EXPECT_EQ(p.color[1], glm::dvec4(13, 1, 0.333333333333333, 1));
  EXPECT_TRUE(gradient_opacity_is_trivial(p));
  // Not one of the presets (its values run -17..235): check the merged function itself.
  for (const std::string& n : volume_preset_names())
    EXPECT_NE(find_volume_preset(n)->scalar_opacity, p.scalar_opacity) << n;
  TransferFunction tf = to_transfer_function(p);
  EXPECT_EQ(tf.points.size(), 7u);  // opacity's values are all colour values too
  glm::vec4 at = evaluate_transfer_function(tf, 58.1764717102051);
  EXPECT_FLOAT_EQ(at.r, 1.0f);
  EXPECT_FLOAT_EQ(at.g, srgb_decode(0.333333333333333f));     // a display colour, decoded
  EXPECT_NEAR(at.a, (58.1764717102051 - 13.0) / 90.0, 1e-6);  // on the 13 -> 103 ramp
  EXPECT_FLOAT_EQ(evaluate_transfer_function(tf, 0.0).a, 0.0f);
}

// Every built-in preset written as a .vp file reads back to the same property.
TEST(VpFile, EveryPresetWrittenAsVpReadsBackTheSame) {
  test::TempDir dir;
  for (const detail::VolumePresetData& d : detail::volume_preset_table()) {
    SCOPED_TRACE(std::string(d.name));
    SlicerVolumeProperty from_file = read_vp_file(dir.write("p.vp", vp_of(d)));
    SlicerVolumeProperty built_in = *find_volume_preset(d.name);
    EXPECT_EQ(from_file.scalar_opacity, built_in.scalar_opacity);
    EXPECT_EQ(from_file.color, built_in.color);
    EXPECT_EQ(from_file.gradient_opacity, built_in.gradient_opacity);
    EXPECT_EQ(from_file.shade, built_in.shade);
    EXPECT_EQ(from_file.specular_power, built_in.specular_power);
  }
}

TEST(VpFile, BadFilesGetOneClearErrorNamingFileLineAndField) {
  test::TempDir dir;
  auto error = [&](const std::string& text) {
    return error_of([&] { read_vp_file(dir.write("bad.vp", text)); });
  };
  const std::string ok_color = "8 0 1 1 1 10 1 1 1";
  std::string e = error(vp("4 0 0 1x 1", ok_color));
  EXPECT_CONTAINS(e, "bad.vp: line 7 (scalar opacity): '1x' is not a number");
  e = error(vp("6 0 0 10 1", ok_color));
  EXPECT_CONTAINS(e, "count 6 does not match the 4 numbers");
  e = error(vp("3 0 0 10", ok_color));
  EXPECT_CONTAINS(e, "not a multiple of 2");
  e = error(vp("4 10 0 0 1", ok_color));
  EXPECT_CONTAINS(e, "is below the previous point's 10 (points must be sorted)");
  e = error(vp("4 0 nan 10 1", ok_color));
  EXPECT_CONTAINS(e, "'nan' is not finite");
  e = error(vp("4 0 0 10 1", "99999999999 0 1 1 1"));
  EXPECT_CONTAINS(e, "line 9 (colour): count 99999999999 is more than 65536 points allow");
  e = error(vp("4 0 0 10 1.5", ok_color));
  EXPECT_CONTAINS(e, "point 1: 1.5 is not in [0, 1]");
  e = error(vp("4 0 0 10 1", "8 0 1 1 1 10 1 2 1"));
  EXPECT_CONTAINS(e, "line 9 (colour): point 1: 2 is not in [0, 1]");
  e = error("1\n1\n0.1\n0.9\n0.2\n10\n4 0 0 10 1\n");
  EXPECT_CONTAINS(e, "has 7 lines, a volume property file has 9 (the gradient opacity is missing)");
  e = error(vp("4 0 0 10 1", ok_color) + "1 2 3\n");
  EXPECT_CONTAINS(e, "line 10: more than the 9 lines");
  e = error("1\n2\n0.1\n0.9\n0.2\n10\n4 0 0 10 1\n4 0 1 1 1\n" + ok_color);
  EXPECT_CONTAINS(e, "line 2 (shade): 2 is not in [0, 1]");
  e = error("");
  EXPECT_CONTAINS(e, "has 0 lines");
  e = error_of([&] { read_vp_file(dir.write("x", "") / "missing.vp"); });
  EXPECT_CONTAINS(e, "missing.vp");
}

TEST(VpFile, BlankLinesAndCarriageReturnsAreAllowed) {
  test::TempDir dir;
  SlicerVolumeProperty p =
      read_vp_file(dir.write("crlf.vp",
                             "1\r\n0\r\n0.1\r\n0.9\r\n\r\n0.2\r\n10\r\n4 0 0 10 1\r\n4 0 1 1 1\r\n"
                             "8 0 1 1 1 10 1 1 1\r\n\r\n"));
  EXPECT_FALSE(p.shade);
  EXPECT_EQ(p.scalar_opacity.size(), 2u);
}

}  // namespace
}  // namespace imx
