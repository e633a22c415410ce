// Compressed voxel data is read to the end of its stream, so its checksum is always checked.
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "temp_dir.hpp"
#include "volume_bytes.hpp"

namespace imx {
namespace {

using test::expect_error;
using test::gzipped;
using test::TempDir;
using test::write_bytes;

const std::string kHeader = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: gzip\n\n";

TEST(GzipIntegrity, ABadChecksumIsRefusedEvenWhenTheDataIsComplete) {
  TempDir dir;
  std::string gz = gzipped(std::string(64, char{9}));
  write_bytes(dir / "good.nrrd", kHeader + gz);
  EXPECT_EQ(read_volume(dir / "good.nrrd").dims, glm::ivec3(4));
  gz[gz.size() - 8] ^= 0x5a;  // the CRC-32 in the gzip trailer
  write_bytes(dir / "crc.nrrd", kHeader + gz);
  expect_error([&] { read_volume(dir / "crc.nrrd"); }, {"crc.nrrd", "corrupt gzip data"});
}

TEST(GzipIntegrity, AStreamCutBeforeItsTrailerIsRefused) {
  TempDir dir;
  std::string gz = gzipped(std::string(64, char{9}));
  write_bytes(dir / "cut.nrrd", kHeader + gz.substr(0, gz.size() - 6));
  expect_error([&] { read_volume(dir / "cut.nrrd"); }, {"cut.nrrd", "ends before its checksum"});
}

TEST(GzipIntegrity, MoreDataThanTheHeaderSaysIsRefusedPastAMegabyte) {
  TempDir dir;
  write_bytes(dir / "long.nrrd", kHeader + gzipped(std::string(3 << 20, char{1})));
  expect_error([&] { read_volume(dir / "long.nrrd"); },
               {"long.nrrd", "holds more than the 64 bytes expected"});
  write_bytes(dir / "bit.nrrd", kHeader + gzipped(std::string(100, char{1})));
  EXPECT_EQ(read_volume(dir / "bit.nrrd").dims, glm::ivec3(4));  // a little extra is tolerated
}

TEST(GzipIntegrity, ACorruptNiftiGzNamesTheGzipData) {
  TempDir dir;
  std::string noise(4000, '\0');
  for (size_t i = 0; i < noise.size(); ++i) noise[i] = static_cast<char>(i * 2654435761u >> 13);
  write_bytes(dir / "bad.nii.gz", gzipped(noise).substr(0, 200));  // cut inside the header
  expect_error([&] { read_volume(dir / "bad.nii.gz"); },
               {"bad.nii.gz", "corrupt or truncated gzip data"});
}

}  // namespace
}  // namespace imx
