// GDCM's image reader and codecs live in a plugin (libimx_dicom_codec.so) that intermix opens on
// the first compressed DICOM file only: start-up and native series never load GDCM's tag
// dictionary (libgdcmDICT, whose static constructor builds it, about 30 ms), and a plugin that
// cannot be loaded is one error naming the file and the paths tried. The dynamic loader's own
// report (LD_DEBUG=files) says what was loaded. Uses ../shared/data/dicom/ts (skipped without it)
// except for the start-up test.
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::contains;
using test::run_cli;
using test::TempDir;

// One image in nine transfer syntaxes: 1 is explicit little endian, 5 JPEG lossless, 7 JPEG-LS
// lossless, 9 JPEG 2000 lossless.
fs::path ts(int n) {
  return test::shared_data("dicom/ts") / fmt::format("{}.dcm", n);
}

TEST(DicomCodecPlugin, StartUpLoadsNoGdcmDictionaryOrCodec) {
  const test::CliResult r = run_cli("--help", "LD_DEBUG=files ");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The loader's report is there and names GDCM's parser, which intermix links.
  ASSERT_TRUE(contains(r.output, "libgdcmDSED")) << r.output.substr(0, 2000);
  EXPECT_FALSE(contains(r.output, "libgdcmDICT"));
  EXPECT_FALSE(contains(r.output, "libgdcmMSFF"));
  EXPECT_FALSE(contains(r.output, "libimx_dicom_codec"));
}

TEST(DicomCodecPlugin, NativeFileLoadsWithoutThePlugin) {
  SKIP_WITHOUT_SHARED_DATA("dicom/ts");
  TempDir dir;
  const fs::path missing = dir / "missing" / "libimx_dicom_codec.so";
  const test::CliResult r =
      run_cli(fmt::format("convert {} -o {}", ts(1).string(), (dir / "1.nii").string()),
              fmt::format("LD_DEBUG=files IMX_DICOM_CODEC={} ", missing.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::file_size(dir / "1.nii") > 64 * 64 * 35);
  EXPECT_FALSE(contains(r.output, "libgdcmDICT"));
  EXPECT_FALSE(contains(r.output, "libimx_dicom_codec"));
}

TEST(DicomCodecPlugin, CompressedFilesLoadThePluginAndMatchTheNativeFile) {
  SKIP_WITHOUT_SHARED_DATA("dicom/ts");
  TempDir dir;
  ASSERT_EQ(
      run_cli(fmt::format("convert {} -o {}", ts(1).string(), (dir / "1.nii").string())).exit_code,
      0);
  const std::string native = test::read_bytes(dir / "1.nii");
  for (int n : {5, 7, 9}) {
    SCOPED_TRACE(n);
    const fs::path out = dir / fmt::format("{}.nii", n);
    const test::CliResult r =
        run_cli(fmt::format("convert {} -o {}", ts(n).string(), out.string()), "LD_DEBUG=files ");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "libimx_dicom_codec.so"));
    EXPECT_TRUE(contains(r.output, "libgdcmDICT"));
    EXPECT_TRUE(test::read_bytes(out) == native);  // the same image, lossless
  }
}

TEST(DicomCodecPlugin, APluginThatCannotBeLoadedIsOneErrorNamingTheFileAndThePath) {
  SKIP_WITHOUT_SHARED_DATA("dicom/ts");
  TempDir dir;
  const fs::path missing = dir / "missing" / "libimx_dicom_codec.so";
  // A missing file, and a file that is no shared library.
  for (const fs::path& plugin : {missing, ts(1)}) {
    SCOPED_TRACE(plugin.string());
    const test::CliResult r =
        run_cli(fmt::format("convert {} -o {}", ts(5).string(), (dir / "5.nii").string()),
                fmt::format("IMX_DICOM_CODEC={} ", plugin.string()));
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_FALSE(fs::exists(dir / "5.nii"));
    // One line names the file, the plugin and the path tried.
    size_t lines = 0;
    for (size_t at = 0; (at = r.output.find(plugin.string(), at)) != std::string::npos;
         at += plugin.string().size()) {
      const size_t begin = r.output.rfind('\n', at) + 1;
      const std::string line = r.output.substr(begin, r.output.find('\n', at) - begin);
      EXPECT_TRUE(contains(line, ts(5).string())) << line;
      EXPECT_TRUE(contains(line, "DICOM codec plugin")) << line;
      ++lines;
    }
    EXPECT_EQ(lines, 1u) << r.output;
  }
}

}  // namespace
}  // namespace imx
