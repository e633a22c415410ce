// MetaImage (.mha/.mhd) reading and writing: ITK's layout, detached data, errors (the round
// trips: volume_round_trip_test.cpp).
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <filesystem>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "encodings.hpp"
#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "pattern_volume.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"
#include "volume_bytes.hpp"

namespace imx {
namespace {

using test::expect_error;
using test::pattern_volume;
using test::raw_bytes;
using test::TempDir;
using test::write_bytes;

// A 2x2x2 MET_SHORT header with `extra` keys before the data, then the data line.
std::string header_2x2x2(const std::string& extra, const std::string& data_file = "LOCAL") {
  return "ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementType = MET_SHORT\n" + extra +
         "ElementDataFile = " + data_file + "\n";
}

TEST(MetaImageWriter, WritesItksKeysWithTheDataLast) {
  TempDir dir;
  VolumeData v = pattern_volume<int16_t>({2, 3, 4});
  v.index_to_world = glm::scale(glm::dmat4(1.0), glm::dvec3(0.5, 2.0, 3.0));
  v.index_to_world[3] = glm::dvec4(1, 2, 3, 1);
  write_metaimage(v, dir / "h.mha", false);
  std::string text = test::read_bytes(dir / "h.mha");
  for (const char* line :
       {"ObjectType = Image\n", "NDims = 3\n", "BinaryDataByteOrderMSB = False\n",
        "CompressedData = False\n", "TransformMatrix = 1 0 0 0 1 0 0 0 1\n", "Offset = 1 2 3\n",
        "ElementSpacing = 0.5 2 3\n", "DimSize = 2 3 4\n", "ElementType = MET_SHORT\n"})
    EXPECT_NE(text.find(line), std::string::npos) << line;
  const std::string last = "ElementDataFile = LOCAL\n";
  EXPECT_EQ(text.size() - text.find(last) - last.size(), 2u * 3 * 4 * 2);

  write_metaimage(v, dir / "z.mha", true);
  text = test::read_bytes(dir / "z.mha");
  size_t key = text.find("CompressedDataSize = ");
  ASSERT_NE(key, std::string::npos);
  size_t declared = std::stoul(text.substr(key + 21));
  EXPECT_EQ(text.size() - text.find(last) - last.size(), declared);
}

TEST(MetaImageWriter, RejectsAnInconsistentVolumeAndLeavesNothing) {
  TempDir dir;
  VolumeData v = pattern_volume<uint8_t>({2, 2, 2});
  v.dims = {3, 2, 2};
  expect_error([&] { write_metaimage(v, dir / "bad.mha"); }, {"bad.mha", "voxels"});
  EXPECT_TRUE(dir.entries().empty());
}

TEST(MetaImageReader, ReadsTheSharedItkFile) {
  SKIP_WITHOUT_SHARED_DATA("mha.mha");
  const std::filesystem::path file = test::shared_data("mha.mha");
  VolumeData v = read_volume(file);
  EXPECT_EQ(v.dims, glm::ivec3(64, 64, 37));
  EXPECT_EQ(v.type(), VoxelType::i16);
  EXPECT_NEAR(v.spacing().x, 3.4375, 1e-9);
  EXPECT_NEAR(v.spacing().y, 3.4375, 1e-9);
  EXPECT_NEAR(v.spacing().z, 3.8, 1e-9);
  // TransformMatrix 1 0 0 0 -1 0 0 0 1: the j axis runs towards -y (anterior) in LPS.
  EXPECT_NEAR(v.index_to_world[1][1], -3.4375, 1e-9);
  EXPECT_NEAR(v.index_to_world[3][0], -108.281, 1e-9);
  auto [lo, hi] = v.range();
  EXPECT_LT(lo, hi);
}

TEST(MetaImageReader, ReadsDetachedBigEndianDoublesWithAHeaderSize) {
  TempDir dir;
  std::vector<double> values = {-1.5, 2.0, 3.25, 4.0, 5.0, 6.0, 7.0, 1e300};
  std::string bytes = raw_bytes(values);
  for (size_t i = 0; i < bytes.size(); i += 8) std::reverse(&bytes[i], &bytes[i] + 8);
  write_bytes(dir / "d.raw", "JUNK" + bytes);
  write_bytes(dir / "d.mhd",
              "ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementType = MET_DOUBLE\n"
              "BinaryDataByteOrderMSB = True\nHeaderSize = 4\nElementSpacing = 1 2 3\n"
              "Offset = 10 20 30\nElementDataFile = d.raw\n");
  VolumeData v = read_volume(dir / "d.mhd");
  ASSERT_EQ(v.type(), VoxelType::f32);
  const auto& f = std::get<VoxelBuffer<float>>(v.voxels);
  EXPECT_EQ(f[0], -1.5f);
  EXPECT_EQ(f[2], 3.25f);
  EXPECT_EQ(f[7], FLT_MAX);  // out-of-range doubles clamp to the float range
  EXPECT_EQ(v.spacing(), glm::dvec3(1, 2, 3));
  EXPECT_EQ(glm::dvec3(v.index_to_world[3]), glm::dvec3(10, 20, 30));
}

TEST(MetaImageReader, ReadsADetachedZrawAndHeaderSizeMinusOne) {
  TempDir dir;
  std::vector<int16_t> values = {1, -2, 3, -4, 5, -6, 7, -8};
  write_bytes(dir / "c.zraw", test::zlib_compressed(raw_bytes(values)));
  write_bytes(dir / "c.mhd", header_2x2x2("CompressedData = True\n", "c.zraw"));
  EXPECT_EQ(std::get<VoxelBuffer<int16_t>>(read_volume(dir / "c.mhd").voxels),
            VoxelBuffer<int16_t>(values));

  write_bytes(dir / "e.raw", "some preamble" + raw_bytes(values));
  write_bytes(dir / "e.mhd", header_2x2x2("HeaderSize = -1\n", "e.raw"));
  EXPECT_EQ(std::get<VoxelBuffer<int16_t>>(read_volume(dir / "e.mhd").voxels),
            VoxelBuffer<int16_t>(values));
}

TEST(MetaImageReader, WidensCharAndReadsA2dImageAsOneSlice) {
  TempDir dir;
  std::vector<int8_t> values = {-128, -1, 0, 127, 5, 6};
  write_bytes(dir / "s.mha",
              "NDims = 2\nDimSize = 3 2\nElementType = MET_CHAR\nElementSpacing = 0.5 0.25\n"
              "TransformMatrix = 0 1 1 0\nOffset = 7 8\nElementDataFile = LOCAL\n" +
                  raw_bytes(values));
  VolumeData v = read_volume(dir / "s.mha");
  EXPECT_EQ(v.dims, glm::ivec3(3, 2, 1));
  ASSERT_EQ(v.type(), VoxelType::i16);
  EXPECT_EQ(std::get<VoxelBuffer<int16_t>>(v.voxels),
            VoxelBuffer<int16_t>({-128, -1, 0, 127, 5, 6}));
  EXPECT_EQ(glm::dvec3(v.index_to_world[0]), glm::dvec3(0, 0.5, 0));
  EXPECT_EQ(glm::dvec3(v.index_to_world[1]), glm::dvec3(0.25, 0, 0));
  EXPECT_EQ(glm::dvec3(v.index_to_world[2]), glm::dvec3(0, 0, 1));
  EXPECT_EQ(glm::dvec3(v.index_to_world[3]), glm::dvec3(7, 8, 0));
}

TEST(MetaImageReaderErrors, TruncatedRawAndCompressedData) {
  TempDir dir;
  write_bytes(dir / "t.mha", header_2x2x2("") + std::string(10, '\0'));
  expect_error([&] { read_volume(dir / "t.mha"); }, {"t.mha", "expected 16 bytes", "found 10"});

  std::string z = test::zlib_compressed(std::string(16, '\x01'));
  write_bytes(dir / "tz.mha", header_2x2x2("CompressedData = True\n") + z.substr(0, z.size() / 2));
  expect_error([&] { read_volume(dir / "tz.mha"); }, {"tz.mha", "expected 16 bytes"});

  write_bytes(dir / "cds.mha",
              header_2x2x2("CompressedData = True\nCompressedDataSize = 5000\n") + z);
  expect_error([&] { read_volume(dir / "cds.mha"); }, {"cds.mha", "CompressedDataSize", "5000"});

  write_bytes(dir / "bad.mha", header_2x2x2("CompressedData = True\n") + "not zlib at all");
  expect_error([&] { read_volume(dir / "bad.mha"); }, {"bad.mha", "corrupt"});
}

TEST(MetaImageReaderErrors, BadElementTypeAndMissingKeys) {
  TempDir dir;
  write_bytes(dir / "ty.mha",
              "NDims = 3\nDimSize = 2 2 2\nElementType = MET_FLOAT_ARRAY\nElementDataFile = "
              "LOCAL\n" +
                  std::string(64, '\0'));
  expect_error([&] { read_volume(dir / "ty.mha"); },
               {"ty.mha", "'ElementType'", "MET_FLOAT_ARRAY"});

  write_bytes(dir / "nd.mha", "NDims = 3\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n" +
                                  std::string(8, '\0'));
  expect_error([&] { read_volume(dir / "nd.mha"); }, {"nd.mha", "missing key 'DimSize'"});

  write_bytes(dir / "nf.mha", "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\n");
  expect_error([&] { read_volume(dir / "nf.mha"); }, {"nf.mha", "'ElementDataFile'"});

  write_bytes(dir / "no.mhd", header_2x2x2("", "missing.raw"));
  expect_error([&] { read_volume(dir / "no.mhd"); }, {"missing.raw", "no.mhd", "no such file"});
}

TEST(MetaImageReaderErrors, BadDimsSpacingAndTransform) {
  TempDir dir;
  auto bad = [&](const std::string& name, const std::string& text,
                 std::initializer_list<std::string> fragments) {
    write_bytes(dir / name, text + std::string(64, '\0'));
    std::vector<std::string> all = {name};
    all.insert(all.end(), fragments);
    std::string message;
    try {
      read_volume(dir / name);
      ADD_FAILURE() << name << ": expected an imx::Error";
    } catch (const Error& e) {
      message = e.what();
    }
    for (const std::string& f : all)
      EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' missing from: " << message;
  };
  const std::string short3 = "NDims = 3\nElementType = MET_SHORT\n";
  bad("huge.mha", short3 + "DimSize = 100000 100000 100000\nElementDataFile = LOCAL\n",
      {"'DimSize'", "voxels"});
  bad("zero.mha", short3 + "DimSize = 2 0 2\nElementDataFile = LOCAL\n", {"'DimSize'"});
  bad("two.mha", short3 + "DimSize = 2 2\nElementDataFile = LOCAL\n", {"'DimSize'", "NDims"});
  bad("nd4.mha", "NDims = 4\nDimSize = 2 2 2 2\nElementType = MET_SHORT\nElementDataFile = LOCAL\n",
      {"'NDims'", "4"});
  bad("nan.mha", header_2x2x2("ElementSpacing = 1 nan 1\n"), {"'ElementSpacing'", "NaN"});
  bad("neg.mha", header_2x2x2("ElementSpacing = 1 -1 1\n"), {"'ElementSpacing'", "positive"});
  bad("tnan.mha", header_2x2x2("TransformMatrix = 1 0 0 0 nan 0 0 0 1\n"),
      {"'TransformMatrix'", "NaN"});
  bad("tsing.mha", header_2x2x2("TransformMatrix = 1 0 0 1 0 0 0 0 1\n"),
      {"'TransformMatrix'", "singular"});
  bad("tcount.mha", header_2x2x2("Rotation = 1 0 0 1\n"), {"'Rotation'", "expected 9"});
  bad("list.mhd", header_2x2x2("", "LIST"), {"'ElementDataFile'", "several files"});
  bad("pat.mhd", header_2x2x2("", "slice%03d.raw 1 2 1"), {"'ElementDataFile'"});
  bad("obj.mha", "ObjectType = Mesh\n" + short3 + "DimSize = 2 2 2\nElementDataFile = LOCAL\n",
      {"'ObjectType'", "Mesh"});
  bad("ascii.mha", header_2x2x2("BinaryData = False\n"), {"'BinaryData'"});
  bad("junk.mha", "\x89PNG\r\n\x1a\n", {"not a MetaImage file"});
}

}  // namespace
}  // namespace imx
