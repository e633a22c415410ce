// A multi-channel OME-Zarr image: `intermix render` draws each channel as its own volume in its
// OME colour and window, a scene's "channel" picks one and "channels" blends them all.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "intermix/io.hpp"
#include "ome_zarr_files.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

// Channel 0 (red) bright over x 0-14, channel 1 (green) over x 15-20, channel 2 (blue) over
// x 21-29, all for y 5-24: three bands of unequal widths, so that swapped colours show. Channel 0
// also holds 80, below its window's start, at y 25-29; `dim` makes its bright band 90 too.
const char* kChannels = R"PY(
for name, bright0 in [('ch.ome.zarr', 1000), ('dim.ome.zarr', 90)]:
    d = np.zeros((3, 10, 30, 30), '<u2')
    d[0, :, 5:25, 0:15] = bright0
    d[1, :, 5:25, 15:21] = 1000
    d[2, :, 5:25, 21:30] = 1000
    d[0, :, 25:30, :] = 80
    image(name, [d], axes='czyx', chunks=[(1, 10, 16, 16)], compressor=Zlib())
    attrs = json.load(open(name + '/.zattrs'))
    window = {'start': 100, 'end': 1000, 'min': 0, 'max': 65535}
    attrs['omero'] = {'channels': [
        {'label': 'Red', 'color': 'FF0000', 'active': True, 'window': window},
        {'label': 'Green', 'color': '00FF00', 'active': True, 'window': window},
        {'label': 'Blue', 'color': '0000FF', 'active': True, 'window': window}]}
    json.dump(attrs, open(name + '/.zattrs', 'w'))
)PY";

// Pixels whose colour is one channel's: that component over twice each other one.
struct Classes {
  int count[3] = {0, 0, 0};
  double mean_x[3] = {0, 0, 0};
  int dark = 0;
};

Classes classify(const Image& image) {
  Classes c;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const glm::vec4 p = image.at(x, y);
      if (p.r + p.g + p.b < 0.05f) ++c.dark;
      for (int k = 0; k < 3; ++k)
        if (p[k] > 0.2f && p[k] > 2.0f * p[(k + 1) % 3] && p[k] > 2.0f * p[(k + 2) % 3]) {
          ++c.count[k];
          c.mean_x[k] += x;
        }
    }
  for (int k = 0; k < 3; ++k)
    if (c.count[k]) c.mean_x[k] /= c.count[k];
  return c;
}

TEST(CliOmeZarrChannels, EachChannelRendersInItsColourAndWindow) {
  SKIP_WITHOUT_ZARR();
  test::TempDir dir;
  ASSERT_TRUE(test::run_zarr_python(dir, kChannels));
  const std::string size = " --width 64 --height 64 --view superior -o ";
  const test::CliResult run =
      test::run_cli("render " + (dir / "ch.ome.zarr").string() + size + (dir / "ch.png").string() +
                    " --save-scene " + (dir / "ch.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string scene = test::read_bytes(dir / "ch.json");
  for (const char* name : {"\"Red\"", "\"Green\"", "\"Blue\"", "\"channel\": 2"})
    EXPECT_TRUE(test::contains(scene, name)) << name << "\n" << scene;
  // info lists the channels as a scene names them.
  const test::CliResult info = test::run_cli("info " + (dir / "ch.ome.zarr").string());
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_TRUE(test::contains(info.output, R"("label":"Green")")) << info.output;
  EXPECT_TRUE(test::contains(info.output, R"("window":[100.0,1000.0])")) << info.output;
  const Classes c = classify(read_png(dir / "ch.png"));
  // Band widths 15, 6 and 9 voxels: red the widest, green the narrowest, green between the two.
  EXPECT_GT(c.count[1], 20);
  EXPECT_GT(c.count[2], c.count[1]);
  EXPECT_GT(c.count[0], c.count[2]);
  EXPECT_GT((c.mean_x[1] - c.mean_x[0]) * (c.mean_x[2] - c.mean_x[1]), 0.0);
  // Channel 0 below its window everywhere: no red anywhere, and its band is background.
  ASSERT_EQ(
      test::run_cli("render " + (dir / "dim.ome.zarr").string() + size + (dir / "dim.png").string())
          .exit_code,
      0);
  const Image dim_image = read_png(dir / "dim.png");
  const Classes dim = classify(dim_image);
  EXPECT_EQ(dim.count[0], 0);
  EXPECT_GT(dim.count[2], dim.count[1]);
  // Every lit pixel is green or blue (but for a few at their bands' edges).
  const int lit = dim_image.width() * dim_image.height() - dim.dark;
  EXPECT_LE(lit, (dim.count[1] + dim.count[2]) * 11 / 10) << lit;
}

TEST(CliOmeZarrChannels, SceneChannelPicksOneAndIsValidated) {
  SKIP_WITHOUT_ZARR();
  test::TempDir dir;
  ASSERT_TRUE(test::run_zarr_python(dir, kChannels));
  const auto scene = [&](const std::string& source) {
    return R"({"camera": {"view": "superior"}, "image": {"width": 64, "height": 64},
               "objects": [{"name": "g", "type": "volume", "source": )" +
           source + "}]}";
  };
  test::write_bytes(dir / "green.json", scene(R"({"file": "ch.ome.zarr", "channel": 1})"));
  const test::CliResult run = test::run_cli("render " + (dir / "green.json").string() + " -o " +
                                            (dir / "green.png").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const Classes c = classify(read_png(dir / "green.png"));
  EXPECT_GT(c.count[1], 20);
  EXPECT_EQ(c.count[0] + c.count[2], 0);
  test::write_bytes(dir / "bad.json", scene(R"({"file": "ch.ome.zarr", "channel": 3})"));
  const test::CliResult bad =
      test::run_cli("render " + (dir / "bad.json").string() + " -o " + (dir / "bad.png").string());
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_TRUE(test::contains(bad.output, "channel")) << bad.output;
  EXPECT_TRUE(test::contains(bad.output, "channel 3 requested")) << bad.output;
  EXPECT_TRUE(test::contains(bad.output, "0 to 2")) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.png"));
  // Every channel blended by maximum into one colour volume: the three bands as before.
  test::write_bytes(dir / "max.json", scene(R"({"file": "ch.ome.zarr", "channels": "max"})"));
  ASSERT_EQ(
      test::run_cli("render " + (dir / "max.json").string() + " -o " + (dir / "max.png").string())
          .exit_code,
      0);
  const Classes m = classify(read_png(dir / "max.png"));
  EXPECT_GT(m.count[1], 20);
  EXPECT_GT(m.count[2], m.count[1]);
  EXPECT_GT(m.count[0], m.count[2]);
  test::write_bytes(dir / "both.json",
                    scene(R"({"file": "ch.ome.zarr", "channels": "add", "channel": 1})"));
  const test::CliResult both = test::run_cli("render " + (dir / "both.json").string() + " -o " +
                                             (dir / "both.png").string());
  EXPECT_NE(both.exit_code, 0);
  EXPECT_TRUE(test::contains(both.output, "not both")) << both.output;
  test::write_bytes(dir / "phantom.json", scene(R"({"phantom": "ct-head", "channel": 0})"));
  const test::CliResult phantom = test::run_cli("render " + (dir / "phantom.json").string() +
                                                " -o " + (dir / "p.png").string());
  EXPECT_NE(phantom.exit_code, 0);
  EXPECT_TRUE(test::contains(phantom.output, "one channel")) << phantom.output;
}

}  // namespace
}  // namespace imx
