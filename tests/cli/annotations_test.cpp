// A scene's annotations through the CLI: `render` draws them where the camera sees them (and
// leaves the rest of the render's bytes), `--no-annotations` leaves them out, and `info
// --annotations` lists what they measure as CSV and JSON.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "intermix/io.hpp"
#include "temp_dir.hpp"

namespace imx::test {
namespace {

// A cube phantom seen from the anterior at 400 mm (30° field of view), and a ruler 60 mm long
// across the view 40 mm above its centre: its image row is 64 - 64 (40 / 400) / tan 15° = 40.1.
std::filesystem::path write_scene(const std::filesystem::path& dir) {
  const auto file = dir / "measured.json";
  write_bytes(file, R"({"camera": {"eye": [0, -400, 0], "target": [0, 0, 0], "up": [0, 0, 1]},
    "image": {"width": 128, "height": 128},
    "objects": [{"name": "cube", "type": "volume", "source": {"phantom": "cube", "size": 16},
                 "transfer_function": {"points": [[0, 1, 1, 1, 0], [1, 1, 1, 1, 0.05]]}}],
    "annotations": [
      {"kind": "ruler", "points": [[-30, 0, 40], [30, 0, 40]], "label": "width"},
      {"kind": "ellipse", "points": [[0, 0, 0], [40, 0, 0], [0, 0, 30]], "volume": "cube"}]})");
  return file;
}

TEST(CliAnnotations, RenderDrawsTheRulerWhereItLies) {
  TempDir dir;
  const std::string scene = write_scene(dir.path()).string();
  const std::string with = (dir / "with.png").string(), without = (dir / "without.png").string();
  CliResult a = run_cli("render " + scene + " -o " + with);
  ASSERT_EQ(a.exit_code, 0) << a.output;
  CliResult b = run_cli("render " + scene + " --no-annotations -o " + without);
  ASSERT_EQ(b.exit_code, 0) << b.output;
  const Image w = read_png(with), o = read_png(without);
  // Along the ruler (x 46..82 of row 40): every pixel changed, to the annotations' orange.
  for (int x = 48; x <= 80; x += 4) {
    EXPECT_NE(w.at(x, 40), o.at(x, 40)) << x;
    EXPECT_GT(w.at(x, 40).r, 0.8f) << x;
    EXPECT_LT(w.at(x, 40).b, 0.5f * w.at(x, 40).r) << x;
  }
  // Far from every annotation and label (the bottom rows, the top rows): the render's own bytes.
  int changed = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x)
      if (y < 30 || y > 100) changed += w.at(x, y) != o.at(x, y);
  EXPECT_EQ(changed, 0);
}

TEST(CliAnnotations, InfoListsTheMeasurements) {
  TempDir dir;
  const std::string scene = write_scene(dir.path()).string();
  CliResult csv = run_cli("info " + scene + " --annotations --csv");
  ASSERT_EQ(csv.exit_code, 0) << csv.output;
  EXPECT_TRUE(contains(csv.output,
                       "index,kind,label,length_mm,angle_deg,area_mm2,volume,units,"
                       "voxels,mean,sd,min,max,points\n"))
      << csv.output;
  EXPECT_TRUE(contains(csv.output, "0,ruler,width,60,,,,,,,,,,-30 0 40; 30 0 40\n")) << csv.output;
  EXPECT_TRUE(contains(csv.output, "1,ellipse,,")) << csv.output;
  CliResult json = run_cli("info " + scene + " --annotations --json");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  const nlohmann::json j = nlohmann::json::parse(json.output);
  EXPECT_EQ(j["annotations"][0]["length_mm"], 60.0);
  EXPECT_NEAR(j["annotations"][1]["area_mm2"].get<double>(), 1200 * 3.14159265358979, 1e-9);
  EXPECT_GT(j["annotations"][1]["voxels"].get<int>(), 0);
  CliResult text = run_cli("info " + scene + " --annotations");
  EXPECT_TRUE(contains(text.output, "0 ruler    width: 60.0 mm")) << text.output;
  CliResult bad = run_cli("info " + scene + " --csv");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_TRUE(contains(bad.output, "--csv applies only with --annotations")) << bad.output;
}

}  // namespace
}  // namespace imx::test
