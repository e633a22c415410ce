#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/colour.hpp"
#include "expect_error.hpp"
#include "presets/paraview_colormap.hpp"
#include "temp_dir.hpp"
#include "volume/tf_lut.hpp"

namespace imx {
namespace {

using test::error_of;

// A map as ParaView writes one, with the keys intermix does not read.
nlohmann::json map(const std::string& name, std::vector<double> rgb,
                   std::vector<double> points = {}) {
  nlohmann::json m = {{"Name", name},
                      {"ColorSpace", "RGB"},
                      {"Creator", "test"},
                      {"NanColor", {1, 1, 0}},
                      {"RGBPoints", rgb}};
  if (!points.empty()) m["Points"] = points;
  return m;
}

TEST(ParaviewColormap, RoundTripOfAWrittenFile) {
  test::TempDir dir;
  nlohmann::json maps =
      nlohmann::json::array({map("Ramp", {0, 0, 0, 0, 100, 1, 0.5, 0}),
                             map("With opacity", {-10, 1, 0, 0, 0, 0, 1, 0, 30, 0, 0, 1},
                                 {-10, 0, 0.5, 0, 20, 0.8, 0.5, 0, 30, 0.4, 0.5, 0})});
  const auto file = dir.write("maps.json", maps.dump(2));

  ParaviewColormap m = read_paraview_colormap(file, "With opacity");
  EXPECT_EQ(m.name, "With opacity");
  EXPECT_TRUE(m.notes.empty());
  const TransferFunction& tf = m.transfer_function;
  ASSERT_EQ(tf.points.size(), 4u);  // -10, 0, 20, 30
  EXPECT_EQ(tf.points[1].value, 0.0);
  EXPECT_EQ(tf.points[1].rgba, glm::vec4(0, 1, 0, 0.8f / 3.0f));
  EXPECT_EQ(tf.points[2].value, 20.0);
  // ParaView's colours are display colours: each merged point decoded (docs/colour.md).
  EXPECT_FLOAT_EQ(tf.points[2].rgba.g, srgb_decode(1.0f / 3.0f));
  EXPECT_FLOAT_EQ(tf.points[2].rgba.a, 0.8f);
  EXPECT_FLOAT_EQ(evaluate_transfer_function(tf, 25.0).a, 0.6f);

  // Without "Points": a linear opacity ramp over the colour range, and a note saying so.
  ParaviewColormap ramp = read_paraview_colormap(file, "Ramp");
  ASSERT_EQ(ramp.notes.size(), 1u);
  EXPECT_CONTAINS(ramp.notes[0], "opacity ramps linearly from 0 at 0 to 1 at 100");
  EXPECT_FLOAT_EQ(evaluate_transfer_function(ramp.transfer_function, 25.0).a, 0.25f);
  // Between two points the colour blends in linear light: half of 0.5 decoded.
  EXPECT_FLOAT_EQ(evaluate_transfer_function(ramp.transfer_function, 50.0).g,
                  0.5f * srgb_decode(0.5f));
  EXPECT_EQ(ramp.transfer_function.unit_distance, 1.0);
}

TEST(ParaviewColormap, OneMapNeedsNoNameAndAnObjectIsOneMap) {
  test::TempDir dir;
  auto one =
      dir.write("one.json", nlohmann::json::array({map("A", {0, 1, 1, 1, 1, 0, 0, 0})}).dump());
  EXPECT_EQ(read_paraview_colormap(one, "").name, "A");
  auto object = dir.write("object.json", map("B", {0, 1, 1, 1, 1, 0, 0, 0}).dump());
  EXPECT_EQ(read_paraview_colormap(object, "").name, "B");
}

TEST(ParaviewColormap, NotesForWhatIsApproximated) {
  test::TempDir dir;
  nlohmann::json m = map("Cool", {0, 0, 0, 1, 1, 1, 0, 0}, {0, 0, 0.3, 0.5, 1, 1, 0.5, 0});
  m["ColorSpace"] = "Diverging";
  ParaviewColormap c = read_paraview_colormap(dir.write("c.json", m.dump()), "");
  ASSERT_EQ(c.notes.size(), 2u);
  EXPECT_CONTAINS(c.notes[0], "midpoints and sharpness other than 0.5 and 0 are read as linear");
  EXPECT_CONTAINS(c.notes[1], "interpolated in RGB, not Diverging");
}

TEST(ParaviewColormap, BadFilesGetOneClearErrorNamingFileAndField) {
  test::TempDir dir;
  auto error = [&](const nlohmann::json& j) {
    return error_of([&] { read_paraview_colormap(dir.write("bad.json", j.dump()), ""); });
  };
  auto error_named = [&](const nlohmann::json& j, const std::string& name) {
    return error_of([&] { read_paraview_colormap(dir.write("bad.json", j.dump()), name); });
  };
  nlohmann::json two = nlohmann::json::array({map("A", {0, 1, 1, 1}), map("B", {0, 1, 1, 1})});
  EXPECT_CONTAINS(error(two), "bad.json: holds 2 colour maps; choose one with \"name\": 'A', 'B'");
  EXPECT_CONTAINS(error_named(two, "C"), "has no colour map named 'C'; it has 'A', 'B'");
  EXPECT_CONTAINS(error(map("A", {0, 1, 1})),
                  "[0] ('A').RGBPoints: has 3 numbers, expected a non-zero multiple of 4");
  EXPECT_CONTAINS(error(map("A", {5, 1, 1, 1, 0, 1, 1, 1})),
                  "RGBPoints[4]: value 0 is below the previous point's 5 (points must be sorted)");
  EXPECT_CONTAINS(error(map("A", {0, 1, 1.5, 1})), "RGBPoints[2]: 1.5 is not in [0, 1]");
  EXPECT_CONTAINS(error(map("A", {0, 1, 1, 1}, {0, 2, 0.5, 0})), "Points[1]: 2 is not in [0, 1]");
  nlohmann::json text_in_list = map("A", {0, 1, 1, 1});
  text_in_list["RGBPoints"][1] = "one";
  EXPECT_CONTAINS(error(text_in_list), "RGBPoints[1]: expected a number, got \"one\"");
  nlohmann::json indexed = {{"Name", "Cats"}, {"IndexedColors", {1, 0, 0}}};
  EXPECT_CONTAINS(error(indexed), "[0] ('Cats').RGBPoints: is missing");
  EXPECT_CONTAINS(error(nlohmann::json::array()), "expected an array of ParaView colour maps");
  EXPECT_CONTAINS(error(nlohmann::json::array({1})), "[0]: expected a colour map object");
  std::vector<double> huge((kMaxParaviewPoints + 1) * 4, 0.5);
  for (size_t i = 0; i < huge.size(); i += 4) huge[i] = static_cast<double>(i);
  EXPECT_CONTAINS(error(map("A", huge)), "has 65537 points, more than 65536");
  std::string e =
      error_of([&] { read_paraview_colormap(dir.write("broken.json", "[{\"Name\": "), ""); });
  EXPECT_CONTAINS(e, "broken.json: not valid JSON");
  EXPECT_EQ(e.find("json.exception"), std::string::npos) << e;
}

}  // namespace
}  // namespace imx
