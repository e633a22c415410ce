#include <cmath>
#include <cstring>
#include <sstream>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "pattern_volume.hpp"
#include "temp_dir.hpp"
#include "volume_bytes.hpp"

namespace imx {
namespace {

using test::expect_error;
using test::gzipped;
using test::pattern_volume;
using test::raw_bytes;
using test::TempDir;
using test::write_bytes;

TEST(NrrdWriter, WritesTheDocumentedHeader) {
  TempDir dir;
  VolumeData v = pattern_volume<int16_t>({2, 3, 4});
  write_nrrd(v, dir / "h.nrrd", false);
  std::string text = test::read_bytes(dir / "h.nrrd");
  for (const char* line :
       {"NRRD0004\n", "type: short\n", "dimension: 3\n", "space: left-posterior-superior\n",
        "sizes: 2 3 4\n", "kinds: domain domain domain\n", "endian: little\n", "encoding: raw\n",
        "space directions: (", "space origin: ("})
    EXPECT_NE(text.find(line), std::string::npos) << line;
  EXPECT_EQ(text.size() - text.find("\n\n") - 2, 2u * 3 * 4 * 2);
}

TEST(NrrdWriter, RejectsAnInconsistentVolumeAndLeavesNothing) {
  TempDir dir;
  VolumeData v = pattern_volume<uint8_t>({2, 2, 2});
  v.dims = {3, 2, 2};
  expect_error([&] { write_nrrd(v, dir / "bad.nrrd"); }, {"bad.nrrd", "voxels"});
  EXPECT_TRUE(dir.entries().empty());
}

TEST(NrrdWriter, IntoAMissingFolderThrowsNamingTheFile) {
  TempDir dir;
  expect_error(
      [&] {
        write_nrrd(pattern_volume<uint8_t>({2, 2, 2}), dir / "no" / "v.nrrd");
      },
      {"v.nrrd"});
  EXPECT_TRUE(dir.entries().empty());
}

TEST(NrrdReader, ConvertsRasToLps) {
  TempDir dir;
  std::vector<uint8_t> data(2 * 2 * 2, 9);
  write_bytes(dir / "ras.nrrd",
              "NRRD0004\n# a comment\ntype: uint8\ndimension: 3\nspace: right-anterior-superior\n"
              "sizes: 2 2 2\nspace directions: (1,0,0) (0, 2, 0) (0,0,3)\n"
              "kinds: domain domain domain\nencoding: raw\nspace origin: (10,20,30)\n"
              "note:=key/value pairs are ignored\n\n" +
                  raw_bytes(data));
  VolumeData v = read_volume(dir / "ras.nrrd");
  glm::dmat4 expected(glm::dvec4(-1, 0, 0, 0), glm::dvec4(0, -2, 0, 0), glm::dvec4(0, 0, 3, 0),
                      glm::dvec4(-10, -20, 30, 1));
  test::expect_same_affine(v.index_to_world, expected, 0.0);
  EXPECT_EQ(v.value_at(1, 1, 1), 9.0);
}

TEST(NrrdReader, UsesSpacingsWhenThereAreNoDirections) {
  TempDir dir;
  std::vector<uint16_t> data(3 * 2 * 2, 1000);
  write_bytes(dir / "sp.nrrd",
              "NRRD0004\ntype: ushort\ndimension: 3\nsizes: 3 2 2\n"
              "spacings: 0.5 nan 2.5\nendian: little\nencoding: raw\n\n" +
                  raw_bytes(data));
  VolumeData v = read_volume(dir / "sp.nrrd");
  EXPECT_EQ(v.type(), VoxelType::u16);
  EXPECT_EQ(v.spacing(), glm::dvec3(0.5, 1.0, 2.5));
  EXPECT_EQ(glm::dvec3(v.index_to_world[3]), glm::dvec3(0.0));
}

TEST(NrrdReader, ReadsADetachedHeaderWithSkips) {
  TempDir dir;
  std::vector<int16_t> data(4 * 3 * 2);
  for (size_t i = 0; i < data.size(); ++i) data[i] = static_cast<int16_t>(i * 100 - 1000);
  write_bytes(dir / "data.raw", "first line\nsecond line\nXYZ" + raw_bytes(data));
  write_bytes(dir / "h.nhdr",
              "NRRD0005\ntype: short\ndimension: 3\nsizes: 4 3 2\nendian: little\nencoding: raw\n"
              "data file: data.raw\nline skip: 2\nbyte skip: 3\n");
  VolumeData v = read_volume(dir / "h.nhdr");
  EXPECT_EQ(std::get<VoxelBuffer<int16_t>>(v.voxels), VoxelBuffer<int16_t>(data));
}

TEST(NrrdReader, ByteSkipMinusOneTakesTheLastBytes) {
  TempDir dir;
  std::vector<uint8_t> data = {1, 2, 3, 4, 5, 6, 7, 8};
  write_bytes(dir / "d.raw", "garbage" + raw_bytes(data));
  write_bytes(dir / "h.nhdr",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\n"
              "encoding: raw\ndata file: d.raw\nbyte skip: -1\n");
  EXPECT_EQ(std::get<VoxelBuffer<uint8_t>>(read_volume(dir / "h.nhdr").voxels),
            VoxelBuffer<uint8_t>(data));
}

TEST(NrrdReader, SwapsBigEndianAndReadsGzip) {
  TempDir dir;
  std::vector<uint16_t> big = {0x0102, 0x0304, 0xA0B0, 0x0001, 0, 1, 2, 3};
  std::vector<uint16_t> expected;
  for (uint16_t b : big) expected.push_back(static_cast<uint16_t>((b >> 8) | (b << 8)));
  write_bytes(dir / "be.nrrd",
              "NRRD0004\ntype: unsigned short\ndimension: 3\nsizes: 2 2 2\n"
              "endian: big\nencoding: gzip\n\n" +
                  gzipped(raw_bytes(big)));
  EXPECT_EQ(std::get<VoxelBuffer<uint16_t>>(read_volume(dir / "be.nrrd").voxels),
            VoxelBuffer<uint16_t>(expected));
}

TEST(NrrdReader, GzipByteSkipCountsDecompressedBytes) {
  TempDir dir;
  // Large enough that skipping and reading both take several inflate calls.
  std::vector<float> data(64 * 64 * 40);
  for (size_t i = 0; i < data.size(); ++i) data[i] = static_cast<float>(i % 1013) * 0.5f;
  std::string prefix(300000, 'p');
  write_bytes(dir / "d.raw.gz", gzipped(prefix + raw_bytes(data)));
  write_bytes(dir / "h.nhdr",
              "NRRD0004\ntype: float\ndimension: 3\nsizes: 64 64 40\n"
              "endian: little\nencoding: gzip\ndata file: d.raw.gz\n"
              "byte skip: 300000\n");
  EXPECT_EQ(std::get<VoxelBuffer<float>>(read_volume(dir / "h.nhdr").voxels),
            VoxelBuffer<float>(data));
}

TEST(NrrdReader, ConvertsOtherTypesToTheNearestStorage) {
  TempDir dir;
  std::vector<int8_t> i8 = {-128, -1, 0, 1, 2, 3, 4, 127};
  write_bytes(
      dir / "i8.nrrd",
      "NRRD0004\ntype: signed char\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n" + raw_bytes(i8));
  VolumeData a = read_volume(dir / "i8.nrrd");
  ASSERT_EQ(a.type(), VoxelType::i16);
  EXPECT_EQ(a.value_at(0, 0, 0), -128.0);
  EXPECT_EQ(a.value_at(1, 1, 1), 127.0);

  std::vector<int32_t> i32 = {-100000, 5, 6, 7, 8, 9, 10, 100000};
  write_bytes(dir / "i32.nrrd",
              "NRRD0004\ntype: int\ndimension: 3\nsizes: 2 2 2\n"
              "endian: little\nencoding: raw\n\n" +
                  raw_bytes(i32));
  VolumeData b = read_volume(dir / "i32.nrrd");
  ASSERT_EQ(b.type(), VoxelType::f32);
  EXPECT_EQ(b.value_at(0, 0, 0), -100000.0);

  std::vector<double> f64 = {0.5, 1e300, -2.25, 3, 4, 5, 6, 7};
  write_bytes(dir / "f64.nrrd",
              "NRRD0004\ntype: double\ndimension: 3\nsizes: 2 2 2\n"
              "endian: little\nencoding: gz\n\n" +
                  gzipped(raw_bytes(f64)));
  VolumeData c = read_volume(dir / "f64.nrrd");
  ASSERT_EQ(c.type(), VoxelType::f32);
  EXPECT_EQ(c.value_at(0, 0, 0), 0.5);
  EXPECT_TRUE(std::isfinite(c.value_at(1, 0, 0)));  // out of float range: clamped
  EXPECT_EQ(c.value_at(0, 1, 0), -2.25);
}

// ---- bad input: one imx::Error naming the file and the fault, no crash, no huge allocation

const std::string kShortHeader =
    "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 4 4\nendian: little\n";

TEST(NrrdReaderErrors, TruncatedRawData) {
  TempDir dir;
  write_bytes(dir / "t.nrrd", kShortHeader + "encoding: raw\n\n" + std::string(100, 'x'));
  expect_error([&] { read_volume(dir / "t.nrrd"); },
               {"t.nrrd", "expected 128 bytes of voxel data", "found 100"});
}

TEST(NrrdReaderErrors, TruncatedGzipData) {
  TempDir dir;
  std::string full = gzipped(std::string(128, 'a') + std::string(1000, 'b'));
  write_bytes(dir / "tg.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 8 8 16\n"
              "encoding: gzip\n\n" +
                  full.substr(0, full.size() / 2));
  expect_error([&] { read_volume(dir / "tg.nrrd"); }, {"tg.nrrd", "expected 1024 bytes"});
}

TEST(NrrdReaderErrors, CorruptGzip) {
  TempDir dir;
  std::string junk(300, '\x55');
  junk[0] = '\x1f';
  junk[1] = '\x8b';
  junk[2] = 8;
  write_bytes(dir / "bad.nrrd", kShortHeader + "encoding: gzip\n\n" + junk);
  expect_error([&] { read_volume(dir / "bad.nrrd"); }, {"bad.nrrd", "gzip"});
}

TEST(NrrdReaderErrors, GzipTooSmallForTheSizesIsRejectedBeforeAllocating) {
  TempDir dir;
  write_bytes(dir / "bomb.nrrd",
              "NRRD0004\ntype: float\ndimension: 3\nsizes: 1200 1200 1200\n"
              "endian: little\nencoding: gzip\n\n" +
                  gzipped("tiny"));
  expect_error([&] { read_volume(dir / "bomb.nrrd"); },
               {"bomb.nrrd", "cannot inflate to that much"});
}

TEST(NrrdReaderErrors, UnknownType) {
  TempDir dir;
  write_bytes(dir / "ty.nrrd",
              "NRRD0004\ntype: complex\ndimension: 3\nsizes: 1 1 1\n"
              "encoding: raw\n\n12345678");
  expect_error([&] { read_volume(dir / "ty.nrrd"); }, {"ty.nrrd", "'type'", "complex"});
}

TEST(NrrdReaderErrors, ZeroAndHugeSizes) {
  TempDir dir;
  write_bytes(dir / "z.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 0 4\n"
              "encoding: raw\n\n");
  expect_error([&] { read_volume(dir / "z.nrrd"); }, {"z.nrrd", "'sizes'", "'0'"});
  write_bytes(dir / "n.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 -3 4\n"
              "encoding: raw\n\n");
  expect_error([&] { read_volume(dir / "n.nrrd"); }, {"n.nrrd", "'sizes'"});
  write_bytes(dir / "h.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 100000 100000 100000\n"
              "encoding: raw\n\n");
  expect_error([&] { read_volume(dir / "h.nrrd"); }, {"h.nrrd", "'sizes'", "voxels"});
}

TEST(NrrdReaderErrors, NanInSpaceDirections) {
  TempDir dir;
  write_bytes(dir / "nan.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\n"
              "space: LPS\nspace directions: (1,0,0) (0,nan,0) (0,0,1)\n"
              "encoding: raw\n\nx");
  expect_error([&] { read_volume(dir / "nan.nrrd"); }, {"nan.nrrd", "space directions", "NaN"});
}

TEST(NrrdReaderErrors, SingularSpaceDirections) {
  TempDir dir;
  write_bytes(dir / "sing.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\n"
              "space: LPS\nspace directions: (1,0,0) (2,0,0) (0,0,1)\n"
              "encoding: raw\n\nx");
  expect_error([&] { read_volume(dir / "sing.nrrd"); }, {"sing.nrrd", "singular"});
}

TEST(NrrdReaderErrors, MissingFields) {
  TempDir dir;
  write_bytes(dir / "m.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nencoding: raw\n\nx");
  expect_error([&] { read_volume(dir / "m.nrrd"); }, {"m.nrrd", "missing field 'sizes'"});
  write_bytes(dir / "e.nrrd",
              "NRRD0004\ntype: short\ndimension: 3\nsizes: 1 1 1\n"
              "encoding: raw\n\nxx");
  expect_error([&] { read_volume(dir / "e.nrrd"); }, {"e.nrrd", "missing field 'endian'"});
}

TEST(NrrdReaderErrors, UnsupportedDimensionEncodingSpaceAndKinds) {
  TempDir dir;
  write_bytes(dir / "d.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 5\nsizes: 1 1 1 1 1\n"
              "encoding: raw\n\nx");
  expect_error([&] { read_volume(dir / "d.nrrd"); }, {"d.nrrd", "'dimension'", "5"});
  // 2-D images are no volumes (as before 4-D files were read).
  write_bytes(dir / "2d.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 2\nsizes: 1 1\n"
              "encoding: raw\n\nx");
  expect_error([&] { read_volume(dir / "2d.nrrd"); }, {"2d.nrrd", "'dimension'", "2"});
  write_bytes(dir / "enc.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\n"
              "encoding: zrle\n\nx");
  expect_error([&] { read_volume(dir / "enc.nrrd"); }, {"enc.nrrd", "'encoding'", "zrle"});
  write_bytes(dir / "sp.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\n"
              "space: right-anterior-inferior\nencoding: raw\n\nx");
  expect_error([&] { read_volume(dir / "sp.nrrd"); }, {"sp.nrrd", "'space'"});
  write_bytes(dir / "k.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 3 1 1\n"
              "kinds: RGB-color domain domain\nencoding: raw\n\nxyz");
  expect_error([&] { read_volume(dir / "k.nrrd"); }, {"k.nrrd", "'kinds'", "RGB-color"});
}

TEST(NrrdReaderErrors, NotANrrdFile) {
  TempDir dir;
  write_bytes(dir / "png.nrrd", std::string("\x89PNG\r\n\x1a\n", 8) + std::string(5000, '\0'));
  expect_error([&] { read_volume(dir / "png.nrrd"); }, {"png.nrrd", "not a NRRD file"});
  // A header with no blank line and no data file has no data.
  write_bytes(dir / "nohdr.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\n"
              "encoding: raw\n");
  expect_error([&] { read_volume(dir / "nohdr.nrrd"); }, {"nohdr.nrrd", "no voxel data"});
  // Binary junk with no newline is not read as an endless header line.
  write_bytes(dir / "long.nrrd", "NRRD0004\ntype: " + std::string(200000, 'a'));
  expect_error([&] { read_volume(dir / "long.nrrd"); }, {"long.nrrd", "header line"});
}

TEST(NrrdReaderErrors, DataFileListsAndPatternsMustMatchTheSizes) {
  TempDir dir;
  // One file a slice (subdim 2 by default): two slices need two files.
  write_bytes(dir / "l.nhdr",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\n"
              "encoding: raw\ndata file: LIST\na.raw\nb.raw\nc.raw\n");
  expect_error([&] { read_volume(dir / "l.nhdr"); }, {"l.nhdr", "'data file'", "3 files"});
  write_bytes(dir / "f.nhdr",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\n"
              "encoding: raw\ndata file: slice%03d.raw 0 2 1\n");
  expect_error([&] { read_volume(dir / "f.nhdr"); }, {"f.nhdr", "'data file'", "3 files"});
  // A listed file that is not there is named.
  write_bytes(dir / "a.raw", "abcd");
  write_bytes(dir / "m.nhdr",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\n"
              "encoding: raw\ndata file: LIST\na.raw\ngone.raw\n");
  expect_error([&] { read_volume(dir / "m.nhdr"); }, {"gone.raw", "m.nhdr"});
  // Patterns take one number conversion and nothing else.
  write_bytes(dir / "s.nhdr",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\n"
              "encoding: raw\ndata file: slice%s.raw 0 1 1\n");
  expect_error([&] { read_volume(dir / "s.nhdr"); }, {"s.nhdr", "'data file'", "%d"});
  write_bytes(dir / "z.nhdr",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\n"
              "encoding: raw\ndata file: slice%d.raw 0 1 0\n");
  expect_error([&] { read_volume(dir / "z.nhdr"); }, {"z.nhdr", "'data file'", "step"});
}

TEST(NrrdReaderErrors, MissingDetachedDataFile) {
  TempDir dir;
  write_bytes(dir / "h.nhdr",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\n"
              "encoding: raw\ndata file: gone.raw\n");
  expect_error([&] { read_volume(dir / "h.nhdr"); }, {"gone.raw", "h.nhdr"});
}

}  // namespace
}  // namespace imx
