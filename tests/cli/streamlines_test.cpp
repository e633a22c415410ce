// Streamline objects end to end: a real tract over the MNI template lands inside the brain on
// its own side, `intermix render FILE.tck FILE.tsf` makes a streamlines object with its values,
// and each colouring and selection changes the picture as it should.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "mrtrix_tracks.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"
#include "tubes/tube_geometry.hpp"

namespace imx {
namespace {

constexpr const char* kTract = "neuro/tracts/tract.IFOF_R.trk";
constexpr const char* kTemplate = "neuro/volumes/avg152T1_RL_nifti.nii.gz";

// An orthographic view from above (superior), the whole MNI box in a 128-pixel image.
nlohmann::json from_above() {
  return {{"eye", {0, -20, 500}},
          {"target", {0, -20, 0}},
          {"up", {0, -1, 0}},
          {"projection", "orthographic"},
          {"ortho_height", 240}};
}

Image render_objects(const nlohmann::json& objects) {
  const nlohmann::json scene = {
      {"camera", from_above()},
      {"image", {{"width", 128}, {"height", 128}, {"background", {0, 0, 0, 0}}}},
      {"render", {{"method", "zslab-hybrid"}, {"spp", 1}}},
      {"objects", objects}};
  return render(parse_scene(scene.dump(), ".", "test"));
}

nlohmann::json template_object(double threshold, bool right_half_only) {
  nlohmann::json o = {
      {"name", "t1"},
      {"type", "volume"},
      {"source", {{"file", test::shared_data(kTemplate).string()}}},
      {"transfer_function",
       {{"points", {{threshold - 1, 1, 1, 1, 0}, {threshold, 1, 1, 1, 1}, {1e6, 1, 1, 1, 1}}}}}};
  // Patient right is RAS +x, LPS -x: the kept side is where the normal points.
  if (right_half_only) o["clip_planes"] = {{{"point", {0, 0, 0}}, {"normal", {-1, 0, 0}}}};
  return o;
}

TEST(Streamlines, ATractOverTheMniTemplateLiesInsideTheBrainOnItsSide) {
  SKIP_WITHOUT_SHARED_DATA(kTract, kTemplate);
  // Brain tissue: 40% of the template's largest value (the scalp and skull are darker).
  const VolumeData t1 = read_volume(test::shared_data(kTemplate));
  double largest = 0.0;
  for (int k = 0; k < t1.dims.z; ++k)
    for (int j = 0; j < t1.dims.y; ++j)
      for (int i = 0; i < t1.dims.x; ++i) largest = std::max(largest, t1.value_at(i, j, k));
  const double threshold = 0.4 * largest;
  const Image tract = render_objects(
      nlohmann::json::array({{{"name", "ifof"},
                              {"type", "streamlines"},
                              {"radius", 1.0},
                              {"source", {{"file", test::shared_data(kTract).string()}}}}}));
  const Image right_brain =
      render_objects(nlohmann::json::array({template_object(threshold, true)}));
  nlohmann::json left = template_object(threshold, false);
  left["clip_planes"] = {{{"point", {0, 0, 0}}, {"normal", {1, 0, 0}}}};
  const Image left_brain = render_objects(nlohmann::json::array({left}));
  size_t tract_pixels = 0, in_right = 0, in_left = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) {
      if (tract.at(x, y).a < 0.5f) continue;
      ++tract_pixels;
      in_right += right_brain.at(x, y).a > 0.5f;
      in_left += left_brain.at(x, y).a > 0.5f;
    }
  ASSERT_GT(tract_pixels, 100u);
  // The inferior fronto-occipital fasciculus of the right hemisphere: inside the right brain.
  EXPECT_GE(in_right, tract_pixels * 95 / 100) << in_right << " of " << tract_pixels;
  EXPECT_LE(in_left, tract_pixels * 5 / 100) << in_left << " of " << tract_pixels;
}

// With a volume in the scene (even one that shows nothing) every method still draws the tubes:
// no volume-only fast path may skip them.
TEST(Streamlines, TubesShowBesideAVolumeInEveryMethod) {
  SKIP_WITHOUT_SHARED_DATA(kTract, kTemplate);
  for (const char* method : {"zslab-hybrid", "zslab", "mdvr", "peel", "dfb-sfm", "kbuffer"}) {
    nlohmann::json volume = template_object(1e5, false);  // its TF is clear everywhere
    const nlohmann::json scene = {
        {"camera", from_above()},
        {"image", {{"width", 64}, {"height", 64}, {"background", {0, 0, 0, 0}}}},
        {"render", {{"method", method}, {"spp", 1}}},
        {"objects",
         {volume,
          {{"name", "ifof"},
           {"type", "streamlines"},
           {"radius", 1.5},
           {"source", {{"file", test::shared_data(kTract).string()}}}}}}};
    const Image image = render(parse_scene(scene.dump(), ".", "test"));
    size_t drawn = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) drawn += image.at(x, y).a > 0.5f;
    EXPECT_GT(drawn, 20u) << method;
  }
}

// A .tck and a .tsf written here: two straight streamlines along x at y = -20 and y = +20,
// values rising along the first.
void write_tracks(const std::filesystem::path& tck, const std::filesystem::path& tsf) {
  std::vector<float> a, b, va, vb;
  for (int i = 0; i <= 40; ++i) {
    a.insert(a.end(), {-40.0f + 2.0f * i, -20.0f, 0.0f});
    b.insert(b.end(), {-40.0f + 2.0f * i, 20.0f, 0.0f});
    va.push_back(static_cast<float>(i));
    vb.push_back(0.0f);
  }
  test::write_mrtrix_tracks(tck, "mrtrix tracks", {a, b}, 3);
  test::write_mrtrix_tracks(tsf, "mrtrix track scalars", {va, vb}, 1);
}

// intermix info describes a tractogram (it said ".tck is not a format intermix reads") and a
// connectome; a .tsf alone says it needs its .tck.
TEST(Streamlines, InfoDescribesTractogramsAndConnectomes) {
  test::TempDir dir;
  write_tracks(dir / "two.tck", dir / "two.tsf");
  const test::CliResult r = test::run_cli("info --json " + (dir / "two.tck").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  EXPECT_EQ(j["kind"], "streamlines");
  EXPECT_EQ(j["streamlines"], 2);
  EXPECT_EQ(j["points"], 82);
  EXPECT_EQ(j["points_per_streamline"], nlohmann::json({41, 41}));
  // MRtrix's RAS x, y become LPS -x, -y.
  EXPECT_EQ(j["world_bounds_mm"], nlohmann::json({{-40.0, -20.0, 0.0}, {40.0, 20.0, 0.0}}));
  const test::CliResult tsf = test::run_cli("info " + (dir / "two.tsf").string());
  EXPECT_NE(tsf.exit_code, 0);
  EXPECT_NE(tsf.output.find("needs the .tck"), std::string::npos) << tsf.output;
  const std::filesystem::path jcon = test::shared_data("neuro/connectomes/connectome.jcon");
  if (std::filesystem::exists(jcon)) {
    const test::CliResult c = test::run_cli("info --json " + jcon.string());
    ASSERT_EQ(c.exit_code, 0) << c.output;
    const nlohmann::json cj = nlohmann::json::parse(c.output.substr(c.output.find('{')));
    EXPECT_EQ(cj["kind"], "connectome");
    EXPECT_EQ(cj["nodes"], 4);
    EXPECT_GT(cj["edges"].get<int>(), 0);
  }
}

TEST(Streamlines, RenderOfATckAndItsTsfMakesOneStreamlinesObjectWithValues) {
  test::TempDir dir;
  write_tracks(dir / "two.tck", dir / "two.tsf");
  const std::string png = (dir / "two.png").string(), saved = (dir / "two.json").string();
  const test::CliResult r = test::run_cli(
      fmt::format("render {} {} -o {} --width 64 --height 64 --save-scene {} "
                  "--set objects.two_tck.radius=3",
                  (dir / "two.tck").string(), (dir / "two.tsf").string(), png, saved));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json document = nlohmann::json::parse(test::read_bytes(saved));
  ASSERT_EQ(document["objects"].size(), 1u) << document.dump(2);
  const nlohmann::json& o = document["objects"][0];
  EXPECT_EQ(o["type"], "streamlines");
  EXPECT_EQ(o["source"]["values"][0], (dir / "two.tsf").string());
  const Image image = read_png(png);
  size_t drawn = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      drawn += image.at(x, y).r + image.at(x, y).g + image.at(x, y).b > 0.1f;
  EXPECT_GT(drawn, 20u);
  // A .tsf alone says what it needs.
  const test::CliResult alone =
      test::run_cli(fmt::format("render {} -o {}", (dir / "two.tsf").string(), png));
  EXPECT_NE(alone.exit_code, 0);
  EXPECT_TRUE(test::contains(alone.output, "give it after its .tck")) << alone.output;
}

// The two streamlines seen from above, in each colouring.
Image render_two(const test::TempDir& dir, const nlohmann::json& look) {
  nlohmann::json o = {
      {"name", "two"},
      {"type", "streamlines"},
      {"radius", 2.0},
      {"shading", {{"enabled", false}}},
      {"source", {{"file", (dir / "two.tck").string()}, {"values", {(dir / "two.tsf").string()}}}}};
  if (look.is_object()) o.update(look);
  const nlohmann::json scene = {
      {"camera",
       {{"eye", {0, 0, 300}},
        {"target", {0, 0, 0}},
        {"up", {0, -1, 0}},
        {"projection", "orthographic"},
        {"ortho_height", 100}}},
      {"image", {{"width", 100}, {"height", 100}, {"background", {0, 0, 0, 0}}}},
      {"render", {{"method", "zslab-hybrid"}, {"spp", 1}}},
      {"objects", {o}}};
  return render(parse_scene(scene.dump(), ".", "test"));
}

// The pixel over world LPS (x, y) at z = 0 in render_two's view: 1 pixel per mm, up = -y.
glm::vec4 at_world(const Image& image, double x, double y) {
  const glm::dvec3 right = glm::cross(glm::dvec3(0, 0, -1), glm::dvec3(0, -1, 0));
  const int px = static_cast<int>(std::floor(50 + glm::dot(glm::dvec3(x, y, 0), right)));
  const int py = static_cast<int>(std::floor(50 + y));  // image rows run along +y (up is -y)
  return image.at(px, py);
}

TEST(Streamlines, EachColouringColoursTheTubesItsWay) {
  test::TempDir dir;
  write_tracks(dir / "two.tck", dir / "two.tsf");
  // Direction: both run along x (RAS x = LPS -x): pure red.
  const Image direction = render_two(dir, {});
  for (double y : {-20.0, 20.0}) {
    const glm::vec4 c = at_world(direction, 10.0, y);
    EXPECT_GT(c.r, 0.9f) << y;
    EXPECT_LT(c.g + c.b, 0.05f) << y;
  }
  EXPECT_LT(at_world(direction, 10.0, 0.0).a, 0.01f);  // between them: nothing
  // Fixed colour.
  const glm::vec4 fixed = at_world(render_two(dir, {{"color", {0.0, 1.0, 0.0}}}), 0.0, 20.0);
  EXPECT_GT(fixed.g, 0.9f);
  EXPECT_LT(fixed.r, 0.05f);
  // Point values through grey: the first streamline (TCK y = -20, LPS y = +20) brightens along
  // RAS x, i.e. towards LPS -x; the second is 0 everywhere, the low end.
  const Image values =
      render_two(dir, {{"color_by", "point_value"}, {"value", "two"}, {"colormap", "grey"}});
  const float left = at_world(values, 30.0, 20.0).r, right = at_world(values, -30.0, 20.0).r;
  EXPECT_LT(left, 0.3f);
  EXPECT_GT(right, 0.7f);
  EXPECT_LT(at_world(values, 0.0, -20.0).r, 0.05f);
  EXPECT_GT(at_world(values, 0.0, -20.0).a, 0.9f);
  // A region: a sphere around the first streamline keeps it alone; "avoid" keeps the other.
  const Image through =
      render_two(dir, {{"regions", {{{"sphere", {{"center", {0, 20, 0}}, {"radius", 5}}}}}}});
  EXPECT_GT(at_world(through, 0.0, 20.0).a, 0.9f);
  EXPECT_LT(at_world(through, 0.0, -20.0).a, 0.01f);
  const Image avoid = render_two(
      dir, {{"regions", {{{"sphere", {{"center", {0, 20, 0}}, {"radius", 5}}}, {"avoid", true}}}}});
  EXPECT_LT(at_world(avoid, 0.0, 20.0).a, 0.01f);
  EXPECT_GT(at_world(avoid, 0.0, -20.0).a, 0.9f);
}

TEST(Streamlines, TranslucentTubesLetThroughWhatTheirOpacitySays) {
  test::TempDir dir;
  write_tracks(dir / "two.tck", dir / "two.tsf");
  const glm::vec4 c = at_world(render_two(dir, {{"opacity", 0.3}}), 0.0, 20.0);
  EXPECT_NEAR(c.a, 0.3f, 0.02f);  // one crossing, entry and exit together
}

// Tubes over the memory budget are decimated with a note, not refused: 100 streamlines of 50
// points (5,000 vertices, 4,900 segments) under a budget that holds the vertices and a third of
// the segments' index and BVH draw one streamline in three.
TEST(Streamlines, TubesOverTheMemoryBudgetAreDecimatedWithANote) {
  test::TempDir dir;
  const std::filesystem::path tck = dir / "many.tck";
  std::vector<std::vector<float>> records(100);
  for (int i = 0; i < 100; ++i)
    for (int k = 0; k < 50; ++k) records[i].insert(records[i].end(), {k - 25.0f, i - 50.0f, 0.0f});
  test::write_mrtrix_tracks(tck, "mrtrix tracks", records, 3);
  const std::string scene = fmt::format(
      R"({{"objects": [{{"name": "many", "type": "streamlines", "source": {{"file": "{}"}}}}]}})",
      tck.string());
  // A budget that every second streamline's tubes just exceed, every third's fit, and the
  // 5,000 points themselves fit.
  const uint64_t budget = tube_bytes(100 / 2, 4900 / 2) - 1;
  ASSERT_LT(tube_bytes(100 / 3, 4900 / 3), budget);
  ASSERT_GT(budget, 5000 * sizeof(glm::vec3));
  set_input_limits({budget, false});
  Scene tight;
  try {
    tight = parse_scene(scene, dir.path().string(), "test");
  } catch (...) {
    set_input_limits({});
    throw;
  }
  set_input_limits({});
  ASSERT_EQ(tight.streamlines.size(), 1u);
  EXPECT_EQ(tight.streamlines[0].stride, 3);
  const std::string notes = fmt::format("{}", fmt::join(tight.notes, "\n"));
  EXPECT_NE(notes.find("one in 3 is drawn"), std::string::npos) << notes;
  // Under the default budget nothing is decimated.
  const Scene roomy = parse_scene(scene, dir.path().string(), "test");
  EXPECT_EQ(roomy.streamlines[0].stride, 1);
  for (const std::string& note : roomy.notes) EXPECT_EQ(note.find("is drawn"), std::string::npos);
}

}  // namespace
}  // namespace imx
