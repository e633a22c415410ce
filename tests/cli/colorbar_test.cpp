// render --colorbar end to end: the bars land on the image's right, the rest is the render's own
// bytes; a missing font stops it with one line.
#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "intermix/io.hpp"
#include "temp_dir.hpp"

namespace imx::test {
namespace {

// A cube phantom through a thresholded colour-map transfer function, framed in the image's left.
std::filesystem::path write_overlay_scene(const std::filesystem::path& dir) {
  const auto file = dir / "overlay.json";
  write_bytes(file, R"({"camera": {"eye": [60, -400, 0], "target": [60, 0, 0], "up": [0, 0, 1]},
    "image": {"width": 256, "height": 256},
    "objects": [{"name": "stat", "type": "volume", "units": "t",
      "source": {"phantom": "cube", "size": 16},
      "transfer_function": {"colormap": "hot", "range": [0.2, 1], "threshold": 0.3}}]})");
  return file;
}

TEST(CliColorbar, DrawsOnTheRightAndLeavesTheRenderElsewhere) {
  TempDir dir;
  const std::string scene = write_overlay_scene(dir.path()).string();
  const std::string plain = (dir / "plain.png").string(), bars = (dir / "bars.png").string();
  CliResult a = run_cli("render " + scene + " -o " + plain);
  ASSERT_EQ(a.exit_code, 0) << a.output;
  CliResult b = run_cli("render " + scene + " --colorbar -o " + bars);
  ASSERT_EQ(b.exit_code, 0) << b.output;
  const Image p = read_png(plain), c = read_png(bars);
  int changed_left = 0, changed_right = 0;
  for (int y = 0; y < p.height(); ++y)
    for (int x = 0; x < p.width(); ++x)
      (x < p.width() / 2 ? changed_left : changed_right) += p.at(x, y) != c.at(x, y);
  EXPECT_EQ(changed_left, 0);
  EXPECT_GT(changed_right, 1000);  // one panel with its strip, ticks and title
}

TEST(CliColorbar, MissingFontAndDistributedAreOneLineErrors) {
  TempDir dir;
  const std::string scene = write_overlay_scene(dir.path()).string();
  CliResult r = run_cli("render " + scene + " --colorbar -o " + (dir / "x.png").string(),
                        "IMX_FONT=/nonexistent.ttf ");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("IMX_FONT=/nonexistent.ttf: no such font file"), std::string::npos)
      << r.output;
  CliResult d =
      run_cli("render " + scene + " --colorbar --distributed -o " + (dir / "y.png").string());
  EXPECT_NE(d.exit_code, 0);
  EXPECT_NE(d.output.find("--colorbar does not apply with --distributed"), std::string::npos)
      << d.output;
}

TEST(CliColorbar, OutsideWidensTheImageAndKeepsTheRender) {
  TempDir dir;
  const std::string scene = write_overlay_scene(dir.path()).string();
  const std::string plain = (dir / "plain.png").string(), bars = (dir / "bars.png").string();
  ASSERT_EQ(run_cli("render " + scene + " -o " + plain).exit_code, 0);
  CliResult r = run_cli("render " + scene + " --colorbar --colorbar-position outside -o " + bars);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Image p = read_png(plain), c = read_png(bars);
  ASSERT_GT(c.width(), p.width());
  for (int y = 0; y < p.height(); ++y)
    for (int x = 0; x < p.width(); ++x) ASSERT_EQ(p.at(x, y), c.at(x, y)) << x << "," << y;
  CliResult bad = run_cli("render " + scene + " --colorbar-position middle -o " + bars);
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("middle"), std::string::npos) << bad.output;
}

// intermix figure: the map's threshold against its values, in one line naming the file.
TEST(CliFigure, AThresholdAboveTheMapIsOneLine) {
  TempDir dir;
  const std::string anatomy = (dir / "head.nrrd").string(), map = (dir / "map.nrrd").string();
  ASSERT_EQ(run_cli("phantom ct-head --size 24 -o " + anatomy).exit_code, 0);
  ASSERT_EQ(run_cli("phantom pet --size 24 -o " + map).exit_code, 0);
  const std::string out = (dir / "f.png").string();
  CliResult r = run_cli("figure ortho " + anatomy + " " + map + " --threshold 1e9 -o " + out);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find(map + ": threshold 1e+09 is not below the map's largest value"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  CliResult ok =
      run_cli("figure mosaic " + anatomy + " " + map + " --threshold 0.5 --slices 3 -o " + out);
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_GT(read_png(out).width(), read_png(out).height());
  CliResult cut = run_cli("figure ortho " + anatomy + " --cut 1,2 -o " + out);
  EXPECT_NE(cut.exit_code, 0);
}

}  // namespace
}  // namespace imx::test
