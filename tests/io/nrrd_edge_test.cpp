// NRRD files that an easy reader misreads (issue 31): detached data with skips, axis mins and
// maxs, bzip2, ascii and hex data, data file lists, 4-D files as frames and their DWMRI labels.
// Each is read as teem reads it or refused with one message naming the file and the field.
#include <bzlib.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
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
using test::raw_bytes;
using test::TempDir;
using test::write_bytes;

// bzip2 with libbz2 itself, so the reader is checked against the library's own writer.
std::string bzipped(const std::string& bytes) {
  std::string out(bytes.size() + bytes.size() / 100 + 700, '\0');
  unsigned length = static_cast<unsigned>(out.size());
  EXPECT_EQ(BZ2_bzBuffToBuffCompress(out.data(), &length, const_cast<char*>(bytes.data()),
                                     static_cast<unsigned>(bytes.size()), 9, 0, 0),
            BZ_OK);
  out.resize(length);
  return out;
}

std::vector<int16_t> ramp(size_t n, int start = -50) {
  std::vector<int16_t> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = static_cast<int16_t>(start + static_cast<int>(i) * 3);
  return v;
}

template <class T>
std::vector<T> voxels_of(const VolumeData& v) {
  const VoxelBuffer<T>& b = std::get<VoxelBuffer<T>>(v.voxels);
  return std::vector<T>(b.begin(), b.end());
}

// ---- detached data, byte skip, line skip

TEST(NrrdEdge, DetachedNiftiIsReadWithItsByteSkipAndRefusedWithout) {
  TempDir dir;
  VolumeData v = test::pattern_volume<int16_t>({4, 3, 2});
  write_nifti(v, dir / "v.nii", false);
  const size_t voxel_bytes = v.voxel_count() * 2;
  const size_t header = std::filesystem::file_size(dir / "v.nii") - voxel_bytes;  // 352
  const std::string fields =
      "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nendian: little\nencoding: raw\n"
      "data file: v.nii\n";
  write_bytes(dir / "skip.nhdr", fields + "byte skip: " + std::to_string(header) + "\n");
  EXPECT_EQ(std::get<VoxelBuffer<int16_t>>(read_volume(dir / "skip.nhdr").voxels),
            std::get<VoxelBuffer<int16_t>>(v.voxels));
  // Without it the NIfTI header would be read as voxels.
  write_bytes(dir / "none.nhdr", fields);
  expect_error([&] { read_volume(dir / "none.nhdr"); },
               {"v.nii", "none.nhdr", std::to_string(header) + " bytes more", "'byte skip'"});
  // The same through gzip: the byte skip counts decompressed bytes.
  write_bytes(dir / "v.nii.gz", gzipped(test::read_bytes(dir / "v.nii")));
  const std::string gz_fields =
      "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nendian: little\nencoding: gzip\n"
      "data file: v.nii.gz\n";
  write_bytes(dir / "gz.nhdr", gz_fields + "byte skip: " + std::to_string(header) + "\n");
  EXPECT_EQ(std::get<VoxelBuffer<int16_t>>(read_volume(dir / "gz.nhdr").voxels),
            std::get<VoxelBuffer<int16_t>>(v.voxels));
  write_bytes(dir / "gz-none.nhdr", gz_fields);
  expect_error([&] { read_volume(dir / "gz-none.nhdr"); },
               {"v.nii.gz", std::to_string(header) + " bytes more", "'byte skip'"});
  expect_error(
      [&] {
        read_volume_region(dir / "gz-none.nhdr", {{0, 0, 0}, {1, 1, 1}});
      },
      {"v.nii.gz", "'byte skip'"});
}

TEST(NrrdEdge, RawDataMustFillItsFileUnlessAByteSkipSaysWhere) {
  TempDir dir;
  const std::vector<int16_t> data = ramp(8);
  const std::string fields =
      "NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nendian: little\nencoding: raw\n";
  // Detached, 5 bytes too many: refused; with byte skip -1 the voxels are the last 16 bytes.
  write_bytes(dir / "d.raw", "12345" + raw_bytes(data));
  write_bytes(dir / "long.nhdr", fields + "data file: d.raw\n");
  expect_error([&] { read_volume(dir / "long.nhdr"); }, {"d.raw", "5 bytes more", "byte skip"});
  write_bytes(dir / "end.nhdr", fields + "data file: d.raw\nbyte skip: -1\n");
  EXPECT_EQ(voxels_of<int16_t>(read_volume(dir / "end.nhdr")), data);
  // An explicit byte skip says where the voxels start; what follows them is not read.
  write_bytes(dir / "t.raw", "12345" + raw_bytes(data) + "trailer");
  write_bytes(dir / "skip.nhdr", fields + "data file: t.raw\nbyte skip: 5\n");
  EXPECT_EQ(voxels_of<int16_t>(read_volume(dir / "skip.nhdr")), data);
  // Attached data with bytes after the voxels: the sizes do not describe the file.
  write_bytes(dir / "a.nrrd", fields + "\n" + raw_bytes(data) + "xyz");
  expect_error([&] { read_volume(dir / "a.nrrd"); }, {"a.nrrd", "3 bytes more"});
  expect_error(
      [&] {
        read_volume_region(dir / "a.nrrd", {{0, 0, 0}, {1, 1, 1}});
      },
      {"a.nrrd", "3 bytes more"});
  // byte skip -1 is for raw data only.
  write_bytes(dir / "gz.nhdr",
              "NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nendian: little\n"
              "encoding: gzip\ndata file: d.raw\nbyte skip: -1\n");
  expect_error([&] { read_volume(dir / "gz.nhdr"); }, {"gz.nhdr", "'byte skip' -1", "raw"});
}

TEST(NrrdEdge, LineSkipCountsLinesOfTheFileAndByteSkipDecompressedBytes) {
  TempDir dir;
  const std::vector<int16_t> data = ramp(24);
  // teem: lines are skipped on the file's bytes, then byte skip inside the decompressed stream.
  write_bytes(dir / "d.gz", "first text line\nsecond\n" + gzipped("PREFIX" + raw_bytes(data)));
  write_bytes(dir / "h.nhdr",
              "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nendian: little\n"
              "encoding: gzip\ndata file: d.gz\nline skip: 2\nbyte skip: 6\n");
  EXPECT_EQ(voxels_of<int16_t>(read_volume(dir / "h.nhdr")), data);
  const VolumeData r = read_volume_region(dir / "h.nhdr", {{1, 1, 1}, {3, 3, 2}});
  EXPECT_EQ(r.value_at(0, 0, 0), data[1 + 4 * 1 + 12 * 1]);
  EXPECT_EQ(r.value_at(1, 1, 0), data[2 + 4 * 2 + 12 * 1]);
  // Text data: line skip, then byte skip, both on the file.
  write_bytes(dir / "t.txt", "# a comment line\nXX1 2\n3 4 5 6 7 8\n");
  write_bytes(dir / "t.nhdr",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n"
              "data file: t.txt\nline skip: 1\nbyte skip: 2\n");
  EXPECT_EQ(voxels_of<uint8_t>(read_volume(dir / "t.nhdr")),
            (std::vector<uint8_t>{1, 2, 3, 4, 5, 6, 7, 8}));
  write_bytes(dir / "far.nhdr",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n"
              "data file: t.txt\nline skip: 9\n");
  expect_error([&] { read_volume(dir / "far.nhdr"); }, {"t.txt", "'line skip' 9"});
}

// ---- axis mins and maxs

struct Placement {
  glm::dvec3 spacing, origin;
};

Placement placement_of(const std::filesystem::path& file) {
  const glm::dmat4 m = read_volume_header(file).index_to_world;
  return {{m[0][0], m[1][1], m[2][2]}, glm::dvec3(m[3])};
}

void expect_near(glm::dvec3 a, glm::dvec3 b) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-12) << "component " << c;
}

const std::string kMinMaxFields =
    "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 5 2 4\nencoding: raw\n"
    "axis mins: 0 10 -6\naxis maxs: 4 11 -2\n";

TEST(NrrdEdge, AxisMinsAndMaxsPlaceNodeCentredSamples) {
  TempDir dir;
  write_bytes(dir / "n.nrrd", kMinMaxFields + "centers: node node node\n\n" + std::string(40, 1));
  const Placement p = placement_of(dir / "n.nrrd");
  expect_near(p.spacing, {1.0, 1.0, 4.0 / 3.0});  // (max - min) / (n - 1)
  expect_near(p.origin, {0.0, 10.0, -6.0});       // the first sample is at the min
  EXPECT_EQ(read_volume(dir / "n.nrrd").spacing(), glm::dvec3(1.0, 1.0, 4.0 / 3.0));
}

TEST(NrrdEdge, AxisMinsAndMaxsPlaceCellCentredSamplesAndUnknownIsCell) {
  TempDir dir;
  write_bytes(dir / "c.nrrd",
              kMinMaxFields + "centerings: cell cell cell\n\n" + std::string(40, 1));
  const Placement p = placement_of(dir / "c.nrrd");
  expect_near(p.spacing, {0.8, 0.5, 1.0});    // (max - min) / n
  expect_near(p.origin, {0.4, 10.25, -5.5});  // the first cell's centre
  // No centering given: teem's default, cell.
  write_bytes(dir / "u.nrrd", kMinMaxFields + "centers: ??? ??? ???\n\n" + std::string(40, 1));
  const Placement u = placement_of(dir / "u.nrrd");
  expect_near(u.spacing, p.spacing);
  expect_near(u.origin, p.origin);
  write_bytes(dir / "bad.nrrd",
              kMinMaxFields + "centers: cell middle cell\n\n" + std::string(40, 1));
  expect_error([&] { read_volume(dir / "bad.nrrd"); }, {"bad.nrrd", "'centers'", "middle"});
}

TEST(NrrdEdge, SpacingsWinOverMinsAndMaxsWhichMustAgree) {
  TempDir dir;
  const std::string fields = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 5 2 4\nencoding: raw\n";
  // Spacing and min: the spacing is the step, the min places the first sample.
  write_bytes(dir / "sm.nrrd",
              fields + "spacings: 2 3 0.5\naxis mins: 1 nan 7\ncenters: node node cell\n\n" +
                  std::string(40, 1));
  const Placement a = placement_of(dir / "sm.nrrd");
  expect_near(a.spacing, {2.0, 3.0, 0.5});
  expect_near(a.origin, {1.0, 0.0, 7.25});
  // Spacing, min and max that agree: read; that disagree: refused.
  write_bytes(dir / "ok.nrrd", fields +
                                   "spacings: 1 1 1\naxis mins: 0 0 0\naxis maxs: 4 1 3\n"
                                   "centers: node node node\n\n" +
                                   std::string(40, 1));
  expect_near(placement_of(dir / "ok.nrrd").spacing, {1.0, 1.0, 1.0});
  write_bytes(dir / "no.nrrd", fields +
                                   "spacings: 1 1 1\naxis mins: 0 0 0\naxis maxs: 9 1 3\n"
                                   "centers: node node node\n\n" +
                                   std::string(40, 1));
  expect_error([&] { read_volume(dir / "no.nrrd"); },
               {"no.nrrd", "'spacings', 'axis mins' and 'axis maxs' disagree", "axis 0"});
  // space origin and axis mins would place the same axis twice.
  write_bytes(dir / "so.nrrd",
              fields + "axis mins: 0 0 0\nspace dimension: 3\nspace origin: (1,2,3)\n\n" +
                  std::string(40, 1));
  expect_error([&] { read_volume(dir / "so.nrrd"); }, {"so.nrrd", "'space origin'", "axis mins"});
}

TEST(NrrdEdge, SpaceDirectionsRefuseAxisMinsAndSpacingsAsTeemDoes) {
  TempDir dir;
  const std::string fields =
      "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 5 2 4\nencoding: raw\nspace: LPS\n"
      "space directions: (2,0,0) (0,2,0) (0,0,2)\nspace origin: (1,1,1)\n";
  write_bytes(dir / "m.nrrd", fields + "axis mins: 0 0 0\n\n" + std::string(40, 1));
  expect_error([&] { read_volume(dir / "m.nrrd"); },
               {"m.nrrd", "'axis mins'", "'space directions'"});
  write_bytes(dir / "s.nrrd", fields + "spacings: 1 1 1\n\n" + std::string(40, 1));
  expect_error([&] { read_volume_header(dir / "s.nrrd"); },
               {"s.nrrd", "'spacings'", "'space directions'"});
  // nan is teem's "none": the directions place the volume.
  write_bytes(dir / "nan.nrrd", fields +
                                    "spacings: nan nan nan\naxis maxs: nan nan nan\n"
                                    "centers: cell cell cell\n\n" +
                                    std::string(40, 1));
  const Placement p = placement_of(dir / "nan.nrrd");
  expect_near(p.spacing, {2.0, 2.0, 2.0});
  expect_near(p.origin, {1.0, 1.0, 1.0});
}

// ---- bzip2

const std::string kBzipFields =
    "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nendian: little\nencoding: bzip2\n";

TEST(NrrdEdge, Bzip2DataIsReadWholeAndByRegion) {
  TempDir dir;
  const std::vector<int16_t> data = ramp(24);
  write_bytes(dir / "a.nrrd", kBzipFields + "\n" + bzipped(raw_bytes(data)));
  EXPECT_EQ(voxels_of<int16_t>(read_volume(dir / "a.nrrd")), data);
  const VolumeData r = read_volume_region(dir / "a.nrrd", {{1, 0, 1}, {4, 2, 2}});
  EXPECT_EQ(r.value_at(0, 0, 0), data[1 + 12]);
  EXPECT_EQ(r.value_at(2, 1, 0), data[3 + 4 + 12]);
  // 'bz2', detached, with a byte skip of decompressed bytes, big-endian.
  std::string big = raw_bytes(data);
  for (size_t i = 0; i + 1 < big.size(); i += 2) std::swap(big[i], big[i + 1]);
  write_bytes(dir / "d.raw.bz2", bzipped("skip me" + big));
  write_bytes(dir / "d.nhdr",
              "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nendian: big\nencoding: bz2\n"
              "data file: d.raw.bz2\nbyte skip: 7\n");
  EXPECT_EQ(voxels_of<int16_t>(read_volume(dir / "d.nhdr")), data);
  // Concatenated streams (pbzip2) read as one.
  const std::string bytes = raw_bytes(data);
  write_bytes(dir / "two.nrrd",
              kBzipFields + "\n" + bzipped(bytes.substr(0, 10)) + bzipped(bytes.substr(10)));
  EXPECT_EQ(voxels_of<int16_t>(read_volume(dir / "two.nrrd")), data);
}

TEST(NrrdEdge, Bzip2TruncatedOrCorruptIsRefused) {
  TempDir dir;
  std::vector<int16_t> data(4000);
  for (size_t i = 0; i < data.size(); ++i) data[i] = static_cast<int16_t>((i * 7919) % 3001);
  const std::string fields =
      "NRRD0004\ntype: short\ndimension: 3\nsizes: 20 20 10\nendian: little\nencoding: bzip2\n\n";
  const std::string good = bzipped(raw_bytes(data));
  write_bytes(dir / "good.nrrd", fields + good);
  EXPECT_EQ(voxels_of<int16_t>(read_volume(dir / "good.nrrd")), data);
  // Cut before the end-of-stream marker, even after all the voxels: the CRC is never checked.
  write_bytes(dir / "cut.nrrd", fields + good.substr(0, good.size() - 6));
  expect_error([&] { read_volume(dir / "cut.nrrd"); }, {"cut.nrrd", "bzip2"});
  write_bytes(dir / "half.nrrd", fields + good.substr(0, good.size() / 2));
  expect_error([&] { read_volume(dir / "half.nrrd"); }, {"half.nrrd", "bzip2"});
  expect_error(
      [&] {
        read_volume_region(dir / "half.nrrd", {{0, 0, 0}, {1, 1, 1}});
      },
      {"half.nrrd", "bzip2"});
  // A flipped bit inside the compressed block: the block CRC (or the coding) catches it.
  std::string bad = good;
  bad[bad.size() / 2] = static_cast<char>(bad[bad.size() / 2] ^ 0x10);
  write_bytes(dir / "bad.nrrd", fields + bad);
  expect_error([&] { read_volume(dir / "bad.nrrd"); }, {"bad.nrrd", "corrupt bzip2 data"});
  // Not bzip2 at all.
  write_bytes(dir / "gz.nrrd", fields + gzipped(raw_bytes(data)));
  expect_error([&] { read_volume(dir / "gz.nrrd"); }, {"gz.nrrd", "corrupt bzip2 data", "BZh"});
  // A huge grid from a few bytes is refused before anything is allocated.
  write_bytes(dir / "bomb.nrrd",
              "NRRD0004\ntype: float\ndimension: 3\nsizes: 1200 1200 1200\nendian: little\n"
              "encoding: bzip2\n\n" +
                  bzipped("tiny"));
  expect_error([&] { read_volume(dir / "bomb.nrrd"); }, {"bomb.nrrd", "cannot decompress"});
}

// ---- ascii and hex

const std::string kAsciiU8 =
    "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n\n";

TEST(NrrdEdge, AsciiValuesInAnyLayoutOfLines) {
  TempDir dir;
  write_bytes(dir / "a.nrrd", kAsciiU8 + "0 1\n\n  2\t3 4\r\n5,6\n  255 \n");
  EXPECT_EQ(voxels_of<uint8_t>(read_volume(dir / "a.nrrd")),
            (std::vector<uint8_t>{0, 1, 2, 3, 4, 5, 6, 255}));
  // Floats, with exponents, signs, nan; 'text' and 'txt' name the same encoding. No 'endian'.
  write_bytes(dir / "f.nrrd",
              "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nencoding: text\n\n"
              "1.5 -2e3 +0.25 3\n1e-3 nan 7 -0\n");
  const VolumeData f = read_volume(dir / "f.nrrd");
  EXPECT_EQ(f.value_at(0, 0, 0), 1.5);
  EXPECT_EQ(f.value_at(1, 0, 0), -2000.0);
  EXPECT_EQ(f.value_at(0, 1, 0), 0.25);
  EXPECT_FLOAT_EQ(static_cast<float>(f.value_at(0, 0, 1)), 1e-3f);
  EXPECT_TRUE(std::isnan(f.value_at(1, 0, 1)));
  // Signed 16-bit, whole numbers written with a point, in a region read.
  write_bytes(dir / "s.nrrd",
              "NRRD0004\ntype: short\ndimension: 3\nsizes: 3 2 1\nencoding: txt\n\n"
              "-32768 2.0 3\n4 5e1 32767\n");
  const VolumeData s = read_volume_region(dir / "s.nrrd", {{1, 0, 0}, {3, 2, 1}});
  EXPECT_EQ(voxels_of<int16_t>(s), (std::vector<int16_t>{2, 3, 50, 32767}));
  EXPECT_EQ(read_volume(dir / "s.nrrd").value_at(0, 0, 0), -32768.0);
}

TEST(NrrdEdge, AsciiWithTooFewTooManyOrBadValuesIsRefused) {
  TempDir dir;
  write_bytes(dir / "short.nrrd", kAsciiU8 + "1 2 3 4 5 6 7   \n");
  expect_error([&] { read_volume(dir / "short.nrrd"); },
               {"short.nrrd", "ends after 7 values", "8"});
  write_bytes(dir / "long.nrrd", kAsciiU8 + "1 2 3 4 5 6 7 8 9\n");
  expect_error([&] { read_volume(dir / "long.nrrd"); }, {"long.nrrd", "more than the 8 values"});
  // A region read checks the count too.
  expect_error(
      [&] {
        read_volume_region(dir / "long.nrrd", {{0, 0, 0}, {1, 1, 1}});
      },
      {"long.nrrd", "more than the 8 values"});
  write_bytes(dir / "word.nrrd", kAsciiU8 + "1 2 3 four 5 6 7 8\n");
  expect_error([&] { read_volume(dir / "word.nrrd"); },
               {"word.nrrd", "value 3 'four'", "not a number"});
  write_bytes(dir / "big.nrrd", kAsciiU8 + "1 2 3 4 5 6 7 256\n");
  expect_error([&] { read_volume(dir / "big.nrrd"); },
               {"big.nrrd", "value 7 '256'", "out of range for uint8"});
  write_bytes(dir / "neg.nrrd",
              "NRRD0004\ntype: ushort\ndimension: 3\nsizes: 1 1 2\nencoding: ascii\n\n1 -1\n");
  expect_error([&] { read_volume(dir / "neg.nrrd"); }, {"neg.nrrd", "'-1'", "out of range"});
  write_bytes(dir / "half.nrrd", kAsciiU8 + "1 2 3 4.5 5 6 7 8\n");
  expect_error([&] { read_volume(dir / "half.nrrd"); }, {"half.nrrd", "'4.5'", "whole number"});
  write_bytes(dir / "flt.nrrd",
              "NRRD0004\ntype: float\ndimension: 3\nsizes: 1 1 2\nencoding: ascii\n\n1 1e39\n");
  expect_error([&] { read_volume(dir / "flt.nrrd"); }, {"flt.nrrd", "'1e39'", "out of range"});
  write_bytes(dir / "dbl.nrrd",
              "NRRD0004\ntype: double\ndimension: 3\nsizes: 1 1 2\nencoding: ascii\n\n1 1e400\n");
  expect_error([&] { read_volume(dir / "dbl.nrrd"); }, {"dbl.nrrd", "'1e400'", "out of range"});
}

TEST(NrrdEdge, AsciiTooShortForItsSizesIsRefusedBeforeAllocating) {
  TempDir dir;
  write_bytes(dir / "huge.nrrd",
              "NRRD0004\ntype: float\ndimension: 3\nsizes: 1200 1200 1200\nencoding: ascii\n\n"
              "1 2 3\n");
  expect_error([&] { read_volume(dir / "huge.nrrd"); },
               {"huge.nrrd", "cannot hold the 1728000000 values"});
}

TEST(NrrdEdge, HexBytesAreReadAndBadDigitsRefused) {
  TempDir dir;
  const std::string fields =
      "NRRD0004\ntype: ushort\ndimension: 3\nsizes: 2 1 1\nendian: big\nencoding: hex\n\n";
  write_bytes(dir / "h.nrrd", fields + "01 02\nA0b0\n");
  EXPECT_EQ(voxels_of<uint16_t>(read_volume(dir / "h.nrrd")),
            (std::vector<uint16_t>{0x0102, 0xA0B0}));
  write_bytes(dir / "g.nrrd", fields + "0102 a0bg\n");
  expect_error([&] { read_volume(dir / "g.nrrd"); }, {"g.nrrd", "'g'", "hexadecimal"});
  write_bytes(dir / "odd.nrrd", fields + "0102 a0b 0\n");
  EXPECT_EQ(voxels_of<uint16_t>(read_volume(dir / "odd.nrrd")),
            (std::vector<uint16_t>{0x0102, 0xA0B0}));  // blanks between digits are ignored
  write_bytes(dir / "more.nrrd", fields + "0102 a0b0 ff\n");
  expect_error([&] { read_volume(dir / "more.nrrd"); }, {"more.nrrd", "more than the 4 bytes"});
  write_bytes(dir / "less.nrrd", fields + "0102 a0\n");
  expect_error([&] { read_volume(dir / "less.nrrd"); }, {"less.nrrd", "hex data ends after 3"});
}

// ---- data file lists and patterns

TEST(NrrdEdge, DataFileListAndPatternStackSlices) {
  TempDir dir;
  const std::vector<int16_t> data = ramp(4 * 3 * 2);
  const std::string all = raw_bytes(data);
  write_bytes(dir / "s01.raw", all.substr(0, 24));
  write_bytes(dir / "s02.raw", all.substr(24));
  const std::string fields =
      "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nendian: little\nencoding: raw\n";
  write_bytes(dir / "list.nhdr", fields + "data file: LIST\ns01.raw\ns02.raw\n");
  EXPECT_EQ(voxels_of<int16_t>(read_volume(dir / "list.nhdr")), data);
  write_bytes(dir / "fmt.nhdr", fields + "data file: s%02d.raw 1 2 1\n");
  EXPECT_EQ(voxels_of<int16_t>(read_volume(dir / "fmt.nhdr")), data);
  write_bytes(dir / "down.nhdr", fields + "data file: s%02d.raw 2 1 -1\n");
  const VolumeData down = read_volume(dir / "down.nhdr");  // the second file first
  EXPECT_EQ(down.value_at(0, 0, 0), data[12]);
  EXPECT_EQ(down.value_at(0, 0, 1), data[0]);
  // A region across both files.
  const VolumeData r = read_volume_region(dir / "list.nhdr", {{1, 2, 0}, {3, 3, 2}});
  EXPECT_EQ(voxels_of<int16_t>(r), (std::vector<int16_t>{data[9], data[10], data[21], data[22]}));
  // subdim 3: the elements split equally, here across 3 files of 16 bytes each.
  write_bytes(dir / "p0.raw", all.substr(0, 16));
  write_bytes(dir / "p1.raw", all.substr(16, 16));
  write_bytes(dir / "p2.raw", all.substr(32));
  write_bytes(dir / "sub.nhdr", fields + "data file: LIST 3\np0.raw\np1.raw\np2.raw\n");
  EXPECT_EQ(voxels_of<int16_t>(read_volume(dir / "sub.nhdr")), data);
  // Each file gets the skips, and must hold exactly its share.
  write_bytes(dir / "g1.gz", gzipped("ab" + all.substr(0, 24)));
  write_bytes(dir / "g2.gz", gzipped("cd" + all.substr(24)));
  write_bytes(dir / "gz.nhdr",
              "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nendian: little\n"
              "encoding: gzip\nbyte skip: 2\ndata file: LIST\ng1.gz\ng2.gz\n");
  EXPECT_EQ(voxels_of<int16_t>(read_volume(dir / "gz.nhdr")), data);
  // A single file whose name starts with LIST is no list.
  write_bytes(dir / "LISTS.raw", all);
  write_bytes(dir / "one.nhdr", fields + "data file: LISTS.raw\nline skip: 0\n");
  EXPECT_EQ(voxels_of<int16_t>(read_volume(dir / "one.nhdr")), data);
  write_bytes(dir / "s02.raw", all.substr(24) + "x");
  expect_error([&] { read_volume(dir / "list.nhdr"); }, {"s02.raw", "1 bytes more"});
}

// ---- 4-D files as frames

// Frame f's voxel (i, j, k) of a 4x3x2 grid.
int16_t frame_value(int f, int i, int j, int k) {
  return static_cast<int16_t>(1000 * f + i + 4 * j + 12 * k - 7);
}

void expect_frame(const VolumeData& v, int f) {
  ASSERT_EQ(v.dims, glm::ivec3(4, 3, 2));
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i)
        ASSERT_EQ(v.value_at(i, j, k), frame_value(f, i, j, k))
            << "frame " << f << " voxel " << i << "," << j << "," << k;
}

// The data of `frames` frames with the frame index the fastest (interleaved) or the slowest.
std::string frames_data(int frames, bool interleaved) {
  std::vector<int16_t> v;
  if (interleaved) {
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i)
          for (int f = 0; f < frames; ++f) v.push_back(frame_value(f, i, j, k));
  } else {
    for (int f = 0; f < frames; ++f)
      for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 4; ++i) v.push_back(frame_value(f, i, j, k));
  }
  return raw_bytes(v);
}

TEST(NrrdEdge, ListAxisFastestIsDeinterleavedIntoFrames) {
  TempDir dir;
  // As Slicer writes DWI: kinds list first, its direction none.
  write_bytes(dir / "v.nrrd",
              "NRRD0005\ntype: short\ndimension: 4\nspace: left-posterior-superior\n"
              "sizes: 3 4 3 2\nspace directions: none (2,0,0) (0,3,0) (0,0,4)\n"
              "kinds: list domain domain domain\nendian: little\nencoding: raw\n"
              "space origin: (1,2,3)\n\n" +
                  frames_data(3, true));
  const VolumeHeader h = read_volume_header(dir / "v.nrrd");
  EXPECT_EQ(h.frames, 3);
  EXPECT_EQ(h.dims, glm::ivec3(4, 3, 2));
  EXPECT_TRUE(h.frame_labels.empty());
  EXPECT_EQ(h.index_to_world[1][1], 3.0);
  EXPECT_EQ(glm::dvec3(h.index_to_world[3]), glm::dvec3(1, 2, 3));
  for (int f = 0; f < 3; ++f) expect_frame(read_volume(dir / "v.nrrd", f), f);
  const VolumeData r = read_volume_region(dir / "v.nrrd", {{1, 1, 1}, {3, 3, 2}}, 2);
  EXPECT_EQ(r.value_at(0, 0, 0), frame_value(2, 1, 1, 1));
  EXPECT_EQ(r.value_at(1, 1, 0), frame_value(2, 2, 2, 1));
  // The same gzipped, and bzip2ped: the interleaved stream is read through once.
  const std::string fields =
      "NRRD0005\ntype: short\ndimension: 4\nsizes: 3 4 3 2\nkinds: vector space space space\n"
      "endian: little\n";
  write_bytes(dir / "g.nrrd", fields + "encoding: gzip\n\n" + gzipped(frames_data(3, true)));
  write_bytes(dir / "b.nrrd", fields + "encoding: bzip2\n\n" + bzipped(frames_data(3, true)));
  for (int f = 0; f < 3; ++f) {
    expect_frame(read_volume(dir / "g.nrrd", f), f);
    expect_frame(read_volume(dir / "b.nrrd", f), f);
  }
}

TEST(NrrdEdge, SlowestAxisOfFramesReadsOneFrameOnly) {
  TempDir dir;
  write_bytes(dir / "t.nrrd",
              "NRRD0004\ntype: short\ndimension: 4\nsizes: 4 3 2 5\n"
              "kinds: space space space time\nspacings: 1 1 1 2.5\nendian: little\n"
              "encoding: gzip\n\n" +
                  gzipped(frames_data(5, false)));
  EXPECT_EQ(read_volume_header(dir / "t.nrrd").frames, 5);
  for (int f = 0; f < 5; ++f) expect_frame(read_volume(dir / "t.nrrd", f), f);
  const VolumeData r = read_volume_region(dir / "t.nrrd", {{0, 2, 0}, {4, 3, 2}}, 4);
  EXPECT_EQ(r.value_at(3, 0, 1), frame_value(4, 3, 2, 1));
  // Raw, frames given by 'space directions' alone (its 'none' axis is 'domain' in kinds).
  write_bytes(dir / "r.nrrd",
              "NRRD0004\ntype: short\ndimension: 4\nsizes: 4 3 2 5\n"
              "space: RAS\nspace directions: (1,0,0) (0,1,0) (0,0,1) none\n"
              "kinds: domain domain domain domain\nendian: little\nencoding: raw\n\n" +
                  frames_data(5, false));
  for (int f = 0; f < 5; ++f) expect_frame(read_volume(dir / "r.nrrd", f), f);
  // One file a frame, detached (subdim 3: a file for each 3-D piece).
  const std::string all = frames_data(5, false);
  std::string list;
  for (int f = 0; f < 5; ++f) {
    const std::string name = fmt::format("f{}.raw", f);
    write_bytes(dir / name, all.substr(static_cast<size_t>(f) * 48, 48));
    list += name + "\n";
  }
  write_bytes(dir / "l.nhdr",
              "NRRD0004\ntype: short\ndimension: 4\nsizes: 4 3 2 5\nkinds: domain domain domain "
              "list\nendian: little\nencoding: raw\ndata file: LIST 3\n" +
                  list);
  expect_frame(read_volume(dir / "l.nhdr", 3), 3);
  // A frame axis in the middle: strides, not interleaving.
  std::vector<int16_t> mid;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int f = 0; f < 2; ++f)
        for (int i = 0; i < 4; ++i) mid.push_back(frame_value(f, i, j, k));
  write_bytes(dir / "m.nrrd",
              "NRRD0004\ntype: short\ndimension: 4\nsizes: 4 2 3 2\n"
              "kinds: domain list domain domain\nendian: little\nencoding: raw\n\n" +
                  raw_bytes(mid));
  for (int f = 0; f < 2; ++f) expect_frame(read_volume(dir / "m.nrrd", f), f);
}

TEST(NrrdEdge, FourDFilesWhoseFramesCannotBeToldAreRefused) {
  TempDir dir;
  const std::string data = frames_data(2, false);
  auto file = [&](const std::string& name, const std::string& fields) {
    write_bytes(dir / name,
                "NRRD0004\ntype: short\ndimension: 4\nsizes: 4 3 2 2\n"
                "endian: little\nencoding: raw\n" +
                    fields + "\n" + data);
    return dir / name;
  };
  expect_error([&] { read_volume(file("none.nrrd", "")); },
               {"none.nrrd", "4-D", "'space directions'", "'kinds'"});
  expect_error([&] { read_volume(file("dom.nrrd", "kinds: domain domain domain domain\n")); },
               {"dom.nrrd", "which axis holds the frames"});
  expect_error([&] { read_volume(file("two.nrrd", "kinds: list domain domain time\n")); },
               {"two.nrrd", "'kinds'", "2 non-spatial axes"});
  expect_error(
      [&] { read_volume(file("dirs.nrrd", "space directions: (1,0,0) none (0,0,1) none\n")); },
      {"dirs.nrrd", "'space directions'", "2 'none' entries"});
  expect_error(
      [&] {
        read_volume(file("clash.nrrd",
                         "space directions: (1,0,0) (0,1,0) (0,0,1) none\n"
                         "kinds: list domain domain domain\n"));
      },
      {"clash.nrrd", "'kinds'", "axis 0", "'list'"});
  expect_error([&] { read_volume(file("kind.nrrd", "kinds: domain domain domain lst\n")); },
               {"kind.nrrd", "'lst'", "not a NRRD kind"});
  // Frames out of range, in a 4-D file and in a 3-D one.
  const auto ok = file("ok.nrrd", "kinds: domain domain domain list\n");
  expect_error([&] { read_volume(ok, 2); }, {"ok.nrrd", "frame 2", "0 to 1"});
  expect_error(
      [&] {
        read_volume_region(ok, {{0, 0, 0}, {1, 1, 1}}, -1);
      },
      {"ok.nrrd", "frame -1"});
  write_bytes(dir / "3d.nrrd",
              "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\n"
              "encoding: raw\n\nx");
  expect_error([&] { read_volume(dir / "3d.nrrd", 1); }, {"3d.nrrd", "frame 1"});
  // The data of all frames must be there, whichever is read.
  write_bytes(dir / "cut.nrrd",
              "NRRD0004\ntype: short\ndimension: 4\nsizes: 4 3 2 2\nkinds: domain domain "
              "domain list\nendian: little\nencoding: raw\n\n" +
                  data.substr(0, 60));
  expect_error([&] { read_volume(dir / "cut.nrrd", 0); },
               {"cut.nrrd", "expected 96 bytes", "found 60"});
}

TEST(NrrdEdge, DwmriKeysLabelTheFrames) {
  TempDir dir;
  write_bytes(dir / "dwi.nhdr",
              "NRRD0005\ntype: short\ndimension: 4\nspace: right-anterior-superior\n"
              "sizes: 5 4 3 2\nspace directions: none (1,0,0) (0,1,0) (0,0,1)\n"
              "kinds: list domain domain domain\nendian: little\nencoding: raw\n"
              "measurement frame: (1,0,0) (0,1,0) (0,0,1)\n"
              "modality:=DWMRI\nDWMRI_b-value:=1000\n"
              "DWMRI_gradient_0000:=0 0 0\nDWMRI_gradient_0001:=2 0 0\n"
              "DWMRI_NEX_0001:=2\n"
              "DWMRI_gradient_0003:=0 1.4142135623730951 1.4142135623730951\n"
              "DWMRI_gradient_0004:=   0 1 0\n"
              "data file: dwi.raw\n");
  write_bytes(dir / "dwi.raw", frames_data(5, true));
  const VolumeHeader h = read_volume_header(dir / "dwi.nhdr");
  ASSERT_EQ(h.frames, 5);
  ASSERT_EQ(h.frame_labels.size(), 5u);
  // b scales with the gradient's squared length over the longest one's (here 4).
  const double b[] = {0, 1000, 1000, 1000, 250};
  const glm::dvec3 g[] = {
      {0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {0, std::sqrt(0.5), std::sqrt(0.5)}, {0, 1, 0}};
  for (int f = 0; f < 5; ++f) {
    const FrameLabel& l = h.frame_labels[static_cast<size_t>(f)];
    ASSERT_TRUE(l.b_value && l.b_vector);
    EXPECT_NEAR(*l.b_value, b[f], 1e-9) << f;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR((*l.b_vector)[c], g[f][c], 1e-12) << f;
    EXPECT_EQ(l.text, describe_frame(l));
  }
  EXPECT_EQ(h.frame_labels[1].text, "b=1000 (1,0,0)");
  EXPECT_EQ(h.frame_labels[4].text, "b=250 (0,1,0)");
  expect_frame(read_volume(dir / "dwi.nhdr", 4), 4);

  // Gradients are turned from the measurement frame (here x and y swapped) into the volume's
  // i, j, k axes (here i along RAS +x, j along RAS -z, k along RAS +y).
  write_bytes(dir / "turned.nhdr",
              "NRRD0005\ntype: short\ndimension: 4\nspace: right-anterior-superior\n"
              "sizes: 2 4 3 2\nspace directions: none (2,0,0) (0,0,-1) (0,3,0)\n"
              "kinds: list domain domain domain\nendian: little\nencoding: raw\n"
              "measurement frame: (0,1,0) (1,0,0) (0,0,1)\n"
              "modality:=DWMRI\nDWMRI_b-value:=1000\n"
              "DWMRI_gradient_0000:=0 1 0\nDWMRI_gradient_0001:=0 0 1\n"
              "data file: dwi.raw\n");
  const VolumeHeader turned = read_volume_header(dir / "turned.nhdr");
  ASSERT_EQ(turned.frame_labels.size(), 2u);
  // (0 1 0) measured = RAS +x = the i axis; (0 0 1) measured = RAS +z = minus the j axis.
  EXPECT_NEAR(glm::length(*turned.frame_labels[0].b_vector - glm::dvec3(1, 0, 0)), 0.0, 1e-12);
  EXPECT_NEAR(glm::length(*turned.frame_labels[1].b_vector - glm::dvec3(0, -1, 0)), 0.0, 1e-12);

  // A frame without a gradient, or a gradient too many: refused.
  const std::string head =
      "NRRD0005\ntype: short\ndimension: 4\nsizes: 2 4 3 2\n"
      "kinds: list domain domain domain\nendian: little\nencoding: raw\ndata file: two.raw\n"
      "modality:=DWMRI\nDWMRI_b-value:=800\nDWMRI_gradient_0000:=0 0 0\n";
  write_bytes(dir / "two.raw", frames_data(2, true));
  write_bytes(dir / "gap.nhdr", head);
  expect_error([&] { read_volume_header(dir / "gap.nhdr"); },
               {"gap.nhdr", "DWMRI_gradient_0001", "frame 1 of 2"});
  write_bytes(dir / "extra.nhdr",
              head + "DWMRI_gradient_0001:=1 0 0\nDWMRI_gradient_0002:=0 1 0\n");
  expect_error([&] { read_volume(dir / "extra.nhdr"); }, {"extra.nhdr", "DWMRI_gradient_0002"});
  write_bytes(dir / "nan.nhdr", head + "DWMRI_gradient_0001:=1 x 0\n");
  expect_error([&] { read_volume(dir / "nan.nhdr"); },
               {"nan.nhdr", "DWMRI_gradient_0001", "'1 x 0'"});
}

}  // namespace
}  // namespace imx
