// A TIFF stack given to the CLI: `info` describes it and `render` draws it, whether a
// multi-page OME-TIFF or a folder of slices.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "temp_dir.hpp"
#include "tifffile_files.hpp"

namespace imx {
namespace {

TEST(CliTiff, InfoAndRenderTakeFilesAndFolders) {
  SKIP_WITHOUT_TIFFFILE();
  test::TempDir dir;
  ASSERT_TRUE(test::run_tifffile_python(dir, R"PY(
z, y, x = np.mgrid[0:16, 0:20, 0:24]
data = (1000 * np.exp(-((x - 12)**2 + (y - 10)**2 + (z - 8)**2) / 30.0)).astype('<u2')
tifffile.imwrite('blob.ome.tif', data, compression='zlib',
                 metadata={'axes': 'ZYX', 'PhysicalSizeX': 1000, 'PhysicalSizeXUnit': 'µm',
                           'PhysicalSizeY': 1.5, 'PhysicalSizeYUnit': 'mm',
                           'PhysicalSizeZ': 0.2, 'PhysicalSizeZUnit': 'cm'})
os.makedirs('slices')
for k in range(16):
    tifffile.imwrite(f'slices/blob{k}.tif', data[k])
)PY"));
  const std::string file = (dir / "blob.ome.tif").string(), folder = (dir / "slices").string();
  for (const std::string& image : {file, folder}) {
    SCOPED_TRACE(image);
    const test::CliResult info = test::run_cli("info " + image);
    ASSERT_EQ(info.exit_code, 0) << info.output;
    EXPECT_TRUE(test::contains(info.output, "[24,20,16]")) << info.output;
    EXPECT_TRUE(test::contains(info.output, "uint16")) << info.output;
    const std::string png = image + ".png";
    const test::CliResult render =
        test::run_cli("render " + image + " --width 64 --height 64 -o " + png);
    ASSERT_EQ(render.exit_code, 0) << render.output;
    EXPECT_GT(std::filesystem::file_size(png), 100u);
  }
  EXPECT_TRUE(test::contains(test::run_cli("info " + file).output, "[1.0,1.5,2.0]"));
  // A refused file names the page and field, with a non-zero exit.
  test::write_bytes(dir / "empty.tif", "");
  const test::CliResult bad = test::run_cli("info " + (dir / "empty.tif").string());
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_TRUE(test::contains(bad.output, "empty.tif: not a readable TIFF")) << bad.output;
}

}  // namespace
}  // namespace imx
