// An OME-Zarr folder given to the CLI: `info` describes it and `render` draws it, as for a file.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "ome_zarr_files.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

TEST(CliOmeZarr, InfoAndRenderTakeTheFolder) {
  SKIP_WITHOUT_ZARR();
  test::TempDir dir;
  ASSERT_TRUE(test::run_zarr_python(dir, R"PY(
z, y, x = np.mgrid[0:16, 0:20, 0:24]
data = (1000 * np.exp(-((x - 12)**2 + (y - 10)**2 + (z - 8)**2) / 30.0)).astype('<u2')
image('blob.ome.zarr', [data], chunks=[(8, 8, 8)], compressor=Blosc(),
      scales=[[2.0, 1.5, 1.0]], translations=[[5.0, 6.0, 7.0]])
)PY"));
  const std::string image = (dir / "blob.ome.zarr").string();
  const test::CliResult info = test::run_cli("info " + image);
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_TRUE(test::contains(info.output, "[24,20,16]")) << info.output;
  EXPECT_TRUE(test::contains(info.output, "[1.0,1.5,2.0]")) << info.output;
  const test::CliResult render = test::run_cli("render " + image + " --width 64 --height 64 -o " +
                                               (dir / "blob.png").string());
  ASSERT_EQ(render.exit_code, 0) << render.output;
  EXPECT_GT(std::filesystem::file_size(dir / "blob.png"), 100u);
}

}  // namespace
}  // namespace imx
