#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>

#include <limits>

#include <gtest/gtest.h>
#include <nifti/nifti1.h>
#include <nifti/nifti2.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"
#include "volume_bytes.hpp"

namespace imx {
namespace {

using test::expect_error;
using test::raw_bytes;
using test::TempDir;

// A NIfTI-1 header built by hand, so the reader is checked against the standard rather
// than against nifticlib's writer.
nifti_1_header basic_header(int nx, int ny, int nz, short datatype, short bitpix) {
  nifti_1_header h;
  std::memset(&h, 0, sizeof h);
  h.sizeof_hdr = 348;
  h.dim[0] = 3;
  h.dim[1] = static_cast<short>(nx);
  h.dim[2] = static_cast<short>(ny);
  h.dim[3] = static_cast<short>(nz);
  for (int d = 4; d < 8; ++d) h.dim[d] = 1;
  h.datatype = datatype;
  h.bitpix = bitpix;
  for (int d = 0; d < 8; ++d) h.pixdim[d] = 1.0f;
  h.vox_offset = 352.0f;
  std::memcpy(h.magic, "n+1\0", 4);
  return h;
}

std::string file_bytes(const nifti_1_header& h, const std::string& data) {
  std::string out(reinterpret_cast<const char*>(&h), sizeof h);
  out += std::string(4, '\0');  // no extensions
  return out + data;
}

void write_gz(const std::filesystem::path& file, const std::string& bytes) {
  test::write_bytes(file, test::gzipped(bytes));
}

TEST(NiftiReader, SformConvertsRasToLps) {
  TempDir dir;
  nifti_1_header h = basic_header(3, 2, 2, DT_INT16, 16);
  h.sform_code = 1;
  float rows[3][4] = {
      {0.0f, 2.0f, 0.0f, 10.0f}, {1.5f, 0.0f, 0.0f, -20.0f}, {0.0f, 0.0f, 3.0f, 30.0f}};
  std::memcpy(h.srow_x, rows[0], sizeof rows[0]);
  std::memcpy(h.srow_y, rows[1], sizeof rows[1]);
  std::memcpy(h.srow_z, rows[2], sizeof rows[2]);
  std::vector<int16_t> data(12);
  for (size_t i = 0; i < data.size(); ++i) data[i] = static_cast<int16_t>(100 * i - 500);
  test::write_bytes(dir / "s.nii", file_bytes(h, raw_bytes(data)));
  VolumeData v = read_volume(dir / "s.nii");
  ASSERT_EQ(v.type(), VoxelType::i16);
  EXPECT_EQ(std::get<VoxelBuffer<int16_t>>(v.voxels), VoxelBuffer<int16_t>(data));
  glm::dmat4 m = v.index_to_world;
  EXPECT_EQ(glm::dvec3(m[0]), glm::dvec3(0.0, -1.5, 0.0));
  EXPECT_EQ(glm::dvec3(m[1]), glm::dvec3(-2.0, 0.0, 0.0));
  EXPECT_EQ(glm::dvec3(m[2]), glm::dvec3(0.0, 0.0, 3.0));
  EXPECT_EQ(glm::dvec3(m[3]), glm::dvec3(-10.0, 20.0, 30.0));
}

TEST(NiftiReader, QformAndPixdimFallbacks) {
  TempDir dir;
  nifti_1_header h = basic_header(2, 2, 2, DT_UINT8, 8);
  h.pixdim[1] = 0.5f;
  h.pixdim[2] = 0.75f;
  h.pixdim[3] = 2.0f;
  std::string data(8, '\x07');
  test::write_bytes(dir / "p.nii", file_bytes(h, data));
  VolumeData a = read_volume(dir / "p.nii");
  EXPECT_EQ(glm::dvec3(a.index_to_world[0]), glm::dvec3(-0.5, 0.0, 0.0));
  EXPECT_EQ(glm::dvec3(a.index_to_world[1]), glm::dvec3(0.0, -0.75, 0.0));
  EXPECT_EQ(glm::dvec3(a.index_to_world[2]), glm::dvec3(0.0, 0.0, 2.0));

  // Identity quaternion with an offset: pixdim scaling plus the offset, RAS -> LPS.
  h.qform_code = 1;
  h.pixdim[0] = 1.0f;  // qfac
  h.qoffset_x = 5.0f;
  h.qoffset_y = 6.0f;
  h.qoffset_z = 7.0f;
  test::write_bytes(dir / "q.nii", file_bytes(h, data));
  VolumeData b = read_volume(dir / "q.nii");
  EXPECT_NEAR(b.index_to_world[0][0], -0.5, 1e-6);
  EXPECT_NEAR(b.index_to_world[1][1], -0.75, 1e-6);
  EXPECT_NEAR(b.index_to_world[2][2], 2.0, 1e-6);
  EXPECT_EQ(glm::dvec3(b.index_to_world[3]), glm::dvec3(-5.0, -6.0, 7.0));
}

TEST(NiftiReader, AppliesSlopeAndInterceptAsFloat) {
  TempDir dir;
  nifti_1_header h = basic_header(2, 1, 1, DT_UINT8, 8);
  h.scl_slope = 2.0f;
  h.scl_inter = -1.0f;
  test::write_bytes(dir / "scl.nii", file_bytes(h, std::string("\x03\x0a", 2)));
  VolumeData v = read_volume(dir / "scl.nii");
  ASSERT_EQ(v.type(), VoxelType::f32);
  EXPECT_EQ(v.value_at(0, 0, 0), 5.0);
  EXPECT_EQ(v.value_at(1, 0, 0), 19.0);

  // Slope 1, intercept 0 is no scaling: the native type stays.
  h.scl_slope = 1.0f;
  h.scl_inter = 0.0f;
  test::write_bytes(dir / "one.nii", file_bytes(h, std::string("\x03\x0a", 2)));
  EXPECT_EQ(read_volume(dir / "one.nii").type(), VoxelType::u8);
}

TEST(NiftiReader, ConvertsInt8AndFloat64) {
  TempDir dir;
  nifti_1_header h = basic_header(2, 1, 1, DT_INT8, 8);
  test::write_bytes(dir / "i8.nii", file_bytes(h, std::string("\x80\x7f", 2)));
  VolumeData a = read_volume(dir / "i8.nii");
  ASSERT_EQ(a.type(), VoxelType::i16);
  EXPECT_EQ(a.value_at(0, 0, 0), -128.0);
  EXPECT_EQ(a.value_at(1, 0, 0), 127.0);

  h = basic_header(2, 1, 1, DT_FLOAT64, 64);
  write_gz(dir / "f64.nii.gz", file_bytes(h, raw_bytes(std::vector<double>{0.25, -3.5})));
  VolumeData b = read_volume(dir / "f64.nii.gz");
  ASSERT_EQ(b.type(), VoxelType::f32);
  EXPECT_EQ(b.value_at(1, 0, 0), -3.5);
}

// A 4-D series holds frames: each is read alone, and the header counts them and times them.
TEST(NiftiReader, FourDimensionalFileHoldsFrames) {
  TempDir dir;
  nifti_1_header h = basic_header(2, 2, 1, DT_UINT16, 16);
  h.dim[0] = 4;
  h.dim[4] = 3;
  h.pixdim[4] = 1500.0f;
  h.xyzt_units = NIFTI_UNITS_MM | NIFTI_UNITS_MSEC;
  std::vector<uint16_t> data = {1, 2, 3, 4, 10, 20, 30, 40, 100, 200, 300, 400};
  test::write_bytes(dir / "t.nii", file_bytes(h, raw_bytes(data)));
  write_gz(dir / "t.nii.gz", file_bytes(h, raw_bytes(data)));
  for (const char* name : {"t.nii", "t.nii.gz"}) {
    for (int k = 0; k < 3; ++k) {
      VolumeData v = read_volume(dir / name, k);
      EXPECT_EQ(v.dims, glm::ivec3(2, 2, 1));
      const std::vector<uint16_t> frame(data.begin() + 4 * k, data.begin() + 4 * k + 4);
      EXPECT_EQ(std::get<VoxelBuffer<uint16_t>>(v.voxels), VoxelBuffer<uint16_t>(frame))
          << name << " frame " << k;
    }
    const VolumeHeader header = read_volume_header(dir / name);
    EXPECT_EQ(header.frames, 3);
    ASSERT_EQ(header.frame_labels.size(), 3u);
    EXPECT_DOUBLE_EQ(*header.frame_labels[2].time_s, 3.0);  // 1500 ms steps
    EXPECT_EQ(header.frame_labels[1].text, "t=1.5 s");
    expect_error([&] { read_volume(dir / name, 3); }, {name, "frame 3", "3 frames (0 to 2)"});
  }
  // Without a time unit the frames are counted but not timed.
  h.xyzt_units = NIFTI_UNITS_MM;
  test::write_bytes(dir / "u.nii", file_bytes(h, raw_bytes(data)));
  EXPECT_EQ(read_volume_header(dir / "u.nii").frames, 3);
  EXPECT_TRUE(read_volume_header(dir / "u.nii").frame_labels.empty());
}

// nifticlib reads a .nii without NIfTI's magic as Analyze 7.5, dropping its sform: refused.
TEST(NiftiReaderErrors, ABadMagicIsRefusedNamingIt) {
  TempDir dir;
  nifti_1_header h = basic_header(2, 2, 2, DT_UINT8, 8);
  h.sform_code = 1;
  h.srow_x[0] = h.srow_y[1] = h.srow_z[2] = 2.0f;
  std::memcpy(h.magic, "\0\0\0\0", 4);
  test::write_bytes(dir / "nomagic.nii", file_bytes(h, std::string(8, '\0')));
  expect_error([&] { read_volume(dir / "nomagic.nii"); }, {"nomagic.nii", "magic", "'n+1'"});
  std::memcpy(h.magic, "n+\x01\0", 4);
  test::write_bytes(dir / "odd.nii", file_bytes(h, std::string(8, '\0')));
  expect_error([&] { read_volume_header(dir / "odd.nii"); }, {"odd.nii", "magic is 'n+\\x01'"});
}

// A NIfTI-2 single file built by hand, in both byte orders.
TEST(NiftiReader, Nifti2HeaderBuiltByHand) {
  TempDir dir;
  for (bool big_endian : {false, true}) {
    nifti_2_header h;
    std::memset(&h, 0, sizeof h);
    h.sizeof_hdr = 540;
    std::memcpy(h.magic, "n+2\0\r\n\032\n", 8);
    h.datatype = DT_INT16;
    h.bitpix = 16;
    h.dim[0] = 3;
    h.dim[1] = 3;
    h.dim[2] = 2;
    h.dim[3] = 1;
    for (int d = 4; d < 8; ++d) h.dim[d] = 1;
    for (int d = 0; d < 8; ++d) h.pixdim[d] = 1.0;
    h.vox_offset = 544;
    h.sform_code = 1;
    const double rows[3][4] = {
        {0.0, 2.0, 0.0, 10.125}, {1.5, 0.0, 0.0, -20.0}, {0.0, 0.0, 3.0, 30.0}};
    std::memcpy(h.srow_x, rows[0], sizeof rows[0]);
    std::memcpy(h.srow_y, rows[1], sizeof rows[1]);
    std::memcpy(h.srow_z, rows[2], sizeof rows[2]);
    std::vector<int16_t> data = {-5, 4, 3, 2, 1, 0};
    std::string bytes(reinterpret_cast<const char*>(&h), sizeof h);
    bytes += std::string(4, '\0') + raw_bytes(data);
    if (big_endian) {
      // Every field and voxel reversed: the header's fields by their sizes.
      auto flip = [&](size_t at, size_t size) {
        std::reverse(bytes.begin() + static_cast<long>(at),
                     bytes.begin() + static_cast<long>(at + size));
      };
      flip(0, 4);
      flip(12, 2);
      flip(14, 2);
      for (int d = 0; d < 8; ++d) flip(16 + 8 * d, 8);
      for (int d = 0; d < 8; ++d) flip(104 + 8 * d, 8);
      flip(168, 8);
      flip(348, 4);
      for (int k = 0; k < 12; ++k) flip(400 + 8 * k, 8);
      for (size_t i = 0; i < data.size(); ++i) flip(544 + 2 * i, 2);
    }
    const char* name = big_endian ? "be.nii" : "le.nii";
    test::write_bytes(dir / name, bytes);
    VolumeData v = read_volume(dir / name);
    ASSERT_EQ(v.type(), VoxelType::i16) << name;
    EXPECT_EQ(std::get<VoxelBuffer<int16_t>>(v.voxels), VoxelBuffer<int16_t>(data)) << name;
    EXPECT_EQ(glm::dvec3(v.index_to_world[0]), glm::dvec3(0.0, -1.5, 0.0)) << name;
    EXPECT_EQ(glm::dvec3(v.index_to_world[1]), glm::dvec3(-2.0, 0.0, 0.0)) << name;
    EXPECT_EQ(glm::dvec3(v.index_to_world[3]), glm::dvec3(-10.125, 20.0, 30.0)) << name;
  }
}

TEST(NiftiReaderErrors, TruncatedData) {
  TempDir dir;
  nifti_1_header h = basic_header(4, 4, 4, DT_FLOAT32, 32);
  test::write_bytes(dir / "t.nii", file_bytes(h, std::string(100, '\0')));
  expect_error([&] { read_volume(dir / "t.nii"); },
               {"t.nii", "expected 256 bytes of voxel data", "found 100"});
  write_gz(dir / "t.nii.gz", file_bytes(h, std::string(100, '\0')));
  expect_error([&] { read_volume(dir / "t.nii.gz"); }, {"t.nii.gz", "expected 256 bytes"});
}

TEST(NiftiReaderErrors, BadHeaderTwoDimensionsAndUnsupportedType) {
  TempDir dir;
  test::write_bytes(dir / "junk.nii", std::string(600, 'j'));
  expect_error([&] { read_volume(dir / "junk.nii"); }, {"junk.nii", "sizeof_hdr"});
  test::write_bytes(dir / "short.nii", "n+1");
  expect_error([&] { read_volume(dir / "short.nii"); }, {"short.nii", "too short"});
  nifti_1_header bad = basic_header(2, 2, 2, DT_UINT8, 8);
  bad.dim[0] = 9;
  test::write_bytes(dir / "dim0.nii", file_bytes(bad, std::string(8, '\0')));
  expect_error([&] { read_volume(dir / "dim0.nii"); }, {"dim0.nii", "dim[0]"});

  nifti_1_header h = basic_header(4, 4, 1, DT_UINT8, 8);
  h.dim[0] = 2;
  test::write_bytes(dir / "flat.nii", file_bytes(h, std::string(16, '\0')));
  expect_error([&] { read_volume(dir / "flat.nii"); }, {"flat.nii", "2 dimensions"});

  h = basic_header(1, 1, 1, DT_COMPLEX64, 64);  // RGB24 and RGBA32 read: colour_nifti_test.cpp
  test::write_bytes(dir / "complex.nii", file_bytes(h, std::string(8, '\0')));
  expect_error([&] { read_volume(dir / "complex.nii"); }, {"complex.nii", "datatype"});

  h = basic_header(30000, 30000, 30000, DT_UINT8, 8);
  write_gz(dir / "huge.nii.gz", file_bytes(h, ""));
  expect_error([&] { read_volume(dir / "huge.nii.gz"); }, {"huge.nii.gz", "voxels"});
}

TEST(NiftiReaderErrors, AVoxOffsetInsideTheHeaderAndNonFinitePlacementAreRefused) {
  TempDir dir;
  nifti_1_header h = basic_header(2, 2, 2, DT_UINT8, 8);
  h.vox_offset = 0.0f;  // nifticlib would read the data from byte 348
  test::write_bytes(dir / "off.nii", file_bytes(h, std::string(8, '\0')));
  expect_error([&] { read_volume(dir / "off.nii"); }, {"off.nii", "vox_offset is 0", "352"});
  h = basic_header(2, 2, 2, DT_UINT8, 8);
  h.sform_code = 1;
  h.srow_x[0] = h.srow_y[1] = h.srow_z[2] = 1.0f;
  h.srow_y[3] = std::numeric_limits<float>::quiet_NaN();  // nifticlib would make it 0
  test::write_bytes(dir / "srow.nii", file_bytes(h, std::string(8, '\0')));
  expect_error([&] { read_volume(dir / "srow.nii"); }, {"srow.nii", "srow_y[3] is nan"});
  h = basic_header(2, 2, 2, DT_UINT8, 8);
  h.qform_code = 1;
  h.qoffset_z = std::numeric_limits<float>::infinity();
  test::write_bytes(dir / "q.nii", file_bytes(h, std::string(8, '\0')));
  expect_error([&] { read_volume(dir / "q.nii"); }, {"q.nii", "qoffset_z is inf"});
}

// ---- the shared real files

using test::shared_data;

TEST(SharedData, FlairNrrdAndNiftiAgree) {
  SKIP_WITHOUT_SHARED_DATA("FLAIR.nrrd", "FLAIR.nii.gz");
  VolumeData a = read_volume(shared_data("FLAIR.nrrd"));
  VolumeData b = read_volume(shared_data("FLAIR.nii.gz"));
  EXPECT_EQ(a.dims, glm::ivec3(124, 160, 140));
  EXPECT_EQ(a.dims, b.dims);
  ASSERT_EQ(a.type(), VoxelType::u8);
  ASSERT_EQ(b.type(), a.type());
  EXPECT_TRUE(std::get<VoxelBuffer<uint8_t>>(a.voxels) == std::get<VoxelBuffer<uint8_t>>(b.voxels));
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      EXPECT_NEAR(a.index_to_world[c][r], b.index_to_world[c][r], 1e-3) << c << "," << r;
  // The corners of the grid land at the same world points.
  glm::dvec4 far(a.dims.x - 1, a.dims.y - 1, a.dims.z - 1, 1.0);
  EXPECT_LT(glm::length(glm::dvec3(a.index_to_world * far - b.index_to_world * far)), 1e-3);
}

TEST(SharedData, HippoLoads) {
  SKIP_WITHOUT_SHARED_DATA("hippo.nii.gz");
  VolumeData v = read_volume(shared_data("hippo.nii.gz"));
  EXPECT_GT(v.voxel_count(), 0u);
  EXPECT_NO_THROW(v.validate("hippo"));
  auto [lo, hi] = v.range();
  EXPECT_LT(lo, hi);
}

}  // namespace
}  // namespace imx
