// Data files named inside volume headers stay inside the header's folder unless allowed.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::expect_error;
using test::TempDir;
using test::write_bytes;

const std::string kVoxels(8, '\x07');  // 2x2x2 uint8

std::string nhdr(const std::string& data_file) {
  return "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: " +
         data_file + "\n\n";
}

std::string mhd(const std::string& data_file) {
  return "ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\n"
         "ElementDataFile = " +
         data_file + "\n";
}

class ExternalData : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::create_directories(dir / "scan" / "parts");
    std::filesystem::create_directories(dir / "elsewhere");
    write_bytes(dir / "scan" / "parts" / "v.raw", kVoxels);
    write_bytes(dir / "elsewhere" / "v.raw", kVoxels);
  }
  void TearDown() override { set_input_limits({}); }
  TempDir dir;
};

TEST_F(ExternalData, FilesInTheHeadersFolderOrBelowAreRead) {
  write_bytes(dir / "scan" / "a.nhdr", nhdr("parts/v.raw"));
  EXPECT_EQ(read_volume(dir / "scan" / "a.nhdr").dims, glm::ivec3(2));
  write_bytes(dir / "scan" / "a.mhd", mhd("parts/v.raw"));
  EXPECT_EQ(read_volume(dir / "scan" / "a.mhd").dims, glm::ivec3(2));
}

TEST_F(ExternalData, FilesOutsideAreRefusedUntilAllowed) {
  write_bytes(dir / "scan" / "up.nhdr", nhdr("../elsewhere/v.raw"));
  write_bytes(dir / "scan" / "abs.mhd", mhd((dir / "elsewhere" / "v.raw").string()));
  expect_error(
      [&] { read_volume(dir / "scan" / "up.nhdr"); },
      {"up.nhdr", "field 'data file'", "outside the file's folder", "--allow-external-data"});
  expect_error([&] { read_volume(dir / "scan" / "abs.mhd"); },
               {"abs.mhd", "field 'ElementDataFile'", "outside the file's folder"});
  set_input_limits({0, true});
  EXPECT_EQ(read_volume(dir / "scan" / "up.nhdr").dims, glm::ivec3(2));
  EXPECT_EQ(read_volume(dir / "scan" / "abs.mhd").dims, glm::ivec3(2));
}

TEST_F(ExternalData, ALinkInsideThatLeadsOutsideIsRefused) {
  std::filesystem::create_symlink(dir / "elsewhere" / "v.raw", dir / "scan" / "link.raw");
  write_bytes(dir / "scan" / "l.nhdr", nhdr("link.raw"));
  expect_error([&] { read_volume(dir / "scan" / "l.nhdr"); }, {"outside the file's folder"});
}

}  // namespace
}  // namespace imx
