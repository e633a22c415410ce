// read_volume_region and read_volume_header against crop(read_volume) for every format variant,
// and make_phantom_region / phantom_header against make_phantom.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nifti/nifti1.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "pattern_volume.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"
#include "volume_bytes.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::expect_error;
using test::gzipped;
using test::TempDir;

// Not symmetric along any axis, so a swapped axis or a wrong row offset shows.
constexpr glm::ivec3 kDims{13, 11, 7};

// A value per voxel that differs between neighbours along every axis.
double pattern(int i, int j, int k) {
  return i * 3 + j * 37 + k * 401;
}

// The boxes every variant is read with: whole, single voxels, interior, each face, full rows
// and full slices (which read in one run), in a grid of `d`.
std::vector<VoxelBox> boxes_for(glm::ivec3 d) {
  const glm::ivec3 mid = d / 2;
  return {
      VoxelBox::whole(d),
      {glm::ivec3(0), glm::ivec3(1)},              // first voxel
      {d - 1, d},                                  // last voxel
      {mid, mid + 1},                              // a voxel inside
      {{2, 3, 1}, {d.x - 3, d.y - 2, d.z - 2}},    // interior
      {{0, 2, 1}, {4, d.y - 1, d.z - 1}},          // touches x = 0
      {{d.x - 4, 2, 1}, {d.x, d.y - 1, d.z - 1}},  // touches x = max
      {{2, 0, 1}, {d.x - 2, 3, d.z - 1}},          // touches y = 0
      {{2, d.y - 3, 1}, {d.x - 2, d.y, d.z - 1}},  // touches y = max
      {{2, 1, 0}, {d.x - 2, d.y - 1, 2}},          // touches z = 0
      {{2, 1, d.z - 2}, {d.x - 2, d.y - 1, d.z}},  // touches z = max
      {{0, 2, 1}, {d.x, d.y - 3, d.z - 1}},        // full rows
      {{0, 0, 2}, {d.x, d.y, d.z - 1}},            // full slices
      {{0, d.y - 1, 0}, {d.x, d.y, d.z}},          // the last row of every slice
      {{d.x - 1, 0, 0}, {d.x, d.y, d.z}},          // the last column
  };
}

std::string box_text(const VoxelBox& b) {
  std::ostringstream s;
  s << "[" << b.lo.x << "," << b.hi.x << ")x[" << b.lo.y << "," << b.hi.y << ")x[" << b.lo.z << ","
    << b.hi.z << ")";
  return s.str();
}

// Same dims, type, placement and voxel bytes.
void expect_same(const VolumeData& got, const VolumeData& want, const std::string& where) {
  ASSERT_EQ(got.dims, want.dims) << where;
  ASSERT_EQ(got.type(), want.type()) << where;
  EXPECT_EQ(got.index_to_world, want.index_to_world) << where;
  std::visit(
      [&](const auto& w) {
        using Buffer = std::decay_t<decltype(w)>;
        const auto* g = std::get_if<Buffer>(&got.voxels);
        ASSERT_NE(g, nullptr) << where;
        ASSERT_EQ(g->size(), w.size()) << where;
        EXPECT_EQ(std::memcmp(g->data(), w.data(), w.size() * sizeof(w[0])), 0)
            << where << ": voxels differ";
      },
      want.voxels);
}

// Region reads of every box and the header read, against read_volume.
void check_file(const fs::path& file, const std::vector<VoxelBox>& boxes) {
  const VolumeData whole = read_volume(file);
  const VolumeHeader h = read_volume_header(file);
  EXPECT_EQ(h.dims, whole.dims) << file;
  EXPECT_EQ(h.type, whole.type()) << file;
  EXPECT_EQ(h.index_to_world, whole.index_to_world) << file;
  for (const VoxelBox& box : boxes)
    expect_same(read_volume_region(file, box), crop(whole, box, "whole"),
                file.filename().string() + " " + box_text(box));
}

void check_file(const fs::path& file) {
  check_file(file, boxes_for(read_volume_header(file).dims));
}

// Voxel bytes in file order: `T` elements of pattern(), byte-swapped when `big_endian`.
template <class T>
std::string voxel_bytes(glm::ivec3 d, bool big_endian = false, double scale = 1.0) {
  std::string out;
  for (int k = 0; k < d.z; ++k)
    for (int j = 0; j < d.y; ++j)
      for (int i = 0; i < d.x; ++i) {
        double v = pattern(i, j, k) * scale;
        T t;
        if constexpr (std::is_floating_point_v<T>)
          t = static_cast<T>(v / 7.0 - 100.0);
        else  // wraps within the type's range: still different between neighbours
          t = static_cast<T>(static_cast<int64_t>(v) % 251 - (std::is_signed_v<T> ? 120 : 0));
        char b[sizeof(T)];
        std::memcpy(b, &t, sizeof(T));
        if (big_endian) std::reverse(b, b + sizeof(T));
        out.append(b, sizeof(T));
      }
  return out;
}

std::string nrrd_header(const std::string& type, const std::string& extra) {
  return "NRRD0004\ntype: " + type +
         "\ndimension: 3\nsizes: 13 11 7\nspace: right-anterior-superior\n"
         "space directions: (0.5,0.1,0) (0,1.25,0.2) (0.05,0,2)\nspace origin: (-3,4.5,7.25)\n" +
         extra;
}

// Volumes written by the project's writers, one per storage type.
template <class T>
VolumeData written_volume() {
  return test::pattern_volume<T>(kDims);
}

class VolumeRegion : public ::testing::Test {
 protected:
  TempDir dir;
};

TEST_F(VolumeRegion, NrrdRawAttached) {
  write_nrrd(written_volume<int16_t>(), dir / "a.nrrd", false);
  check_file(dir / "a.nrrd");
  write_nrrd(written_volume<uint16_t>(), dir / "b.nrrd", false);
  check_file(dir / "b.nrrd");
  write_nrrd(written_volume<float>(), dir / "c.nrrd", false);
  check_file(dir / "c.nrrd");
  write_nrrd(written_volume<uint8_t>(), dir / "d.nrrd", false);
  check_file(dir / "d.nrrd");
}

TEST_F(VolumeRegion, NrrdGzip) {
  write_nrrd(written_volume<int16_t>(), dir / "a.nrrd", true);
  check_file(dir / "a.nrrd");
  write_nrrd(written_volume<float>(), dir / "f.nrrd", true);
  check_file(dir / "f.nrrd");
  // Hand-made, with a byte skip inside the compressed data.
  test::write_bytes(dir / "s.nrrd", nrrd_header("uint16",
                                                "endian: little\nencoding: gzip\n"
                                                "byte skip: 5\n\n") +
                                        gzipped("12345" + voxel_bytes<uint16_t>(kDims)));
  check_file(dir / "s.nrrd");
}

TEST_F(VolumeRegion, NrrdDetachedWithLineAndByteSkip) {
  test::write_bytes(dir / "d.nhdr", nrrd_header("int16",
                                                "endian: little\nencoding: raw\nline skip: 2\n"
                                                "byte skip: 3\ndata file: d.raw\n"));
  test::write_bytes(dir / "d.raw", "first line\nsecond\nxyz" + voxel_bytes<int16_t>(kDims));
  check_file(dir / "d.nhdr");
  // byte skip -1: the data is the file's last bytes.
  test::write_bytes(dir / "e.nhdr", nrrd_header("float",
                                                "endian: little\nencoding: raw\n"
                                                "byte skip: -1\ndata file: e.raw\n"));
  test::write_bytes(dir / "e.raw", std::string(17, '#') + voxel_bytes<float>(kDims));
  check_file(dir / "e.nhdr");
  // Detached gzip data.
  test::write_bytes(dir / "g.nhdr",
                    nrrd_header("uint16", "endian: little\nencoding: gzip\ndata file: g.raw.gz\n"));
  test::write_bytes(dir / "g.raw.gz", gzipped(voxel_bytes<uint16_t>(kDims)));
  check_file(dir / "g.nhdr");
}

TEST_F(VolumeRegion, NrrdBigEndianAndConvertedTypes) {
  test::write_bytes(dir / "be.nrrd", nrrd_header("int16", "endian: big\nencoding: raw\n\n") +
                                         voxel_bytes<int16_t>(kDims, true));
  check_file(dir / "be.nrrd");
  test::write_bytes(dir / "bef.nrrd", nrrd_header("float", "endian: big\nencoding: gzip\n\n") +
                                          gzipped(voxel_bytes<float>(kDims, true)));
  check_file(dir / "bef.nrrd");
  // int8 widens to int16, 32/64-bit types narrow to float.
  test::write_bytes(dir / "i8.nrrd",
                    nrrd_header("int8", "encoding: raw\n\n") + voxel_bytes<int8_t>(kDims));
  check_file(dir / "i8.nrrd");
  EXPECT_EQ(read_volume_header(dir / "i8.nrrd").type, VoxelType::i16);
  test::write_bytes(dir / "d.nrrd", nrrd_header("double", "endian: big\nencoding: raw\n\n") +
                                        voxel_bytes<double>(kDims, true));
  check_file(dir / "d.nrrd");
  test::write_bytes(dir / "u32.nrrd", nrrd_header("uint32", "endian: little\nencoding: gzip\n\n") +
                                          gzipped(voxel_bytes<uint32_t>(kDims, false, 1e5)));
  check_file(dir / "u32.nrrd");
  EXPECT_EQ(read_volume_header(dir / "u32.nrrd").type, VoxelType::f32);
}

std::string mhd_header(const std::string& type, const std::string& extra) {
  return "ObjectType = Image\nNDims = 3\nBinaryData = True\nTransformMatrix = 0.8 0.6 0 -0.6 0.8 "
         "0 0 0 1\nOffset = 1.5 -2 30\nElementSpacing = 0.7 1.1 2.5\nDimSize = 13 11 7\n"
         "ElementType = " +
         type + "\n" + extra;
}

TEST_F(VolumeRegion, MetaImageRawAttached) {
  write_metaimage(written_volume<uint16_t>(), dir / "a.mha", false);
  check_file(dir / "a.mha");
  write_metaimage(written_volume<float>(), dir / "f.mha", false);
  check_file(dir / "f.mha");
  test::write_bytes(dir / "msb.mha", mhd_header("MET_SHORT",
                                                "BinaryDataByteOrderMSB = True\n"
                                                "ElementDataFile = LOCAL\n") +
                                         voxel_bytes<int16_t>(kDims, true));
  check_file(dir / "msb.mha");
  test::write_bytes(dir / "c.mha", mhd_header("MET_CHAR", "ElementDataFile = LOCAL\n") +
                                       voxel_bytes<int8_t>(kDims));
  check_file(dir / "c.mha");
}

TEST_F(VolumeRegion, MetaImageDetached) {
  test::write_bytes(dir / "d.mhd", mhd_header("MET_USHORT", "ElementDataFile = d.raw\n"));
  test::write_bytes(dir / "d.raw", voxel_bytes<uint16_t>(kDims));
  check_file(dir / "d.mhd");
  // HeaderSize: bytes before the data; -1: the data is the file's last bytes.
  test::write_bytes(dir / "h.mhd",
                    mhd_header("MET_DOUBLE", "HeaderSize = 9\nElementDataFile = h.raw\n"));
  test::write_bytes(dir / "h.raw", "123456789" + voxel_bytes<double>(kDims));
  check_file(dir / "h.mhd");
  test::write_bytes(dir / "e.mhd",
                    mhd_header("MET_FLOAT", "HeaderSize = -1\nElementDataFile = e.raw\n"));
  test::write_bytes(dir / "e.raw", std::string(33, 'x') + voxel_bytes<float>(kDims));
  check_file(dir / "e.mhd");
}

TEST_F(VolumeRegion, MetaImageCompressed) {
  write_metaimage(written_volume<int16_t>(), dir / "a.mha", true);
  check_file(dir / "a.mha");
  write_metaimage(written_volume<uint8_t>(), dir / "b.mha", true);
  check_file(dir / "b.mha");
  test::write_bytes(dir / "z.mhd", mhd_header("MET_INT",
                                              "CompressedData = True\n"
                                              "ElementDataFile = z.zraw\n"));
  test::write_bytes(dir / "z.zraw", gzipped(voxel_bytes<int32_t>(kDims, false, 1e4)));
  check_file(dir / "z.mhd");
}

// A NIfTI-1 header built by hand, for the types and scalings nifticlib's writer does not make.
nifti_1_header nifti_header(short datatype, short bitpix) {
  nifti_1_header h;
  std::memset(&h, 0, sizeof h);
  h.sizeof_hdr = 348;
  h.dim[0] = 3;
  h.dim[1] = static_cast<short>(kDims.x);
  h.dim[2] = static_cast<short>(kDims.y);
  h.dim[3] = static_cast<short>(kDims.z);
  for (int d = 4; d < 8; ++d) h.dim[d] = 1;
  h.datatype = datatype;
  h.bitpix = bitpix;
  for (int d = 0; d < 8; ++d) h.pixdim[d] = 1.0f;
  h.pixdim[1] = 0.9f;
  h.pixdim[3] = 2.5f;
  h.vox_offset = 352.0f;
  h.sform_code = 1;
  const float srow[3][4] = {{0.9f, 0.1f, 0, -20}, {0, 1.0f, 0.2f, 15}, {0.05f, 0, 2.5f, -7}};
  std::memcpy(h.srow_x, srow[0], sizeof h.srow_x);
  std::memcpy(h.srow_y, srow[1], sizeof h.srow_y);
  std::memcpy(h.srow_z, srow[2], sizeof h.srow_z);
  std::memcpy(h.magic, "n+1\0", 4);
  return h;
}

std::string nifti_bytes(const nifti_1_header& h, const std::string& data) {
  return std::string(reinterpret_cast<const char*>(&h), sizeof h) + std::string(4, '\0') + data;
}

TEST_F(VolumeRegion, NiftiUncompressed) {
  write_nifti(written_volume<int16_t>(), dir / "a.nii", false);
  check_file(dir / "a.nii");
  write_nifti(written_volume<float>(), dir / "f.nii", false);
  check_file(dir / "f.nii");
  test::write_bytes(dir / "i8.nii",
                    nifti_bytes(nifti_header(DT_INT8, 8), voxel_bytes<int8_t>(kDims)));
  check_file(dir / "i8.nii");
  // scl_slope/scl_inter make float32 voxels, in the header too.
  nifti_1_header scaled = nifti_header(DT_UINT16, 16);
  scaled.scl_slope = 0.25f;
  scaled.scl_inter = -3.0f;
  test::write_bytes(dir / "s.nii", nifti_bytes(scaled, voxel_bytes<uint16_t>(kDims)));
  check_file(dir / "s.nii");
  EXPECT_EQ(read_volume_header(dir / "s.nii").type, VoxelType::f32);
}

TEST_F(VolumeRegion, NiftiGzip) {
  write_nifti(written_volume<uint16_t>(), dir / "a.nii.gz", true);
  check_file(dir / "a.nii.gz");
  write_nifti(written_volume<uint8_t>(), dir / "b.nii.gz", true);
  check_file(dir / "b.nii.gz");
  nifti_1_header scaled = nifti_header(DT_INT16, 16);
  scaled.scl_slope = -2.0f;
  scaled.scl_inter = 0.5f;
  test::write_bytes(dir / "s.nii.gz", gzipped(nifti_bytes(scaled, voxel_bytes<int16_t>(kDims))));
  check_file(dir / "s.nii.gz");
}

// The runs a box is read in: one per row, fewer where rows or slices follow each other.
std::vector<std::pair<uint64_t, size_t>> runs(const VoxelBox& box, size_t element) {
  std::vector<std::pair<uint64_t, size_t>> out;
  detail::for_each_box_run(kDims, box, element,
                           [&](uint64_t offset, size_t bytes) { out.emplace_back(offset, bytes); });
  return out;
}

TEST(VoxelBoxRuns, WholeRowsAndSlicesAreReadInOneGo) {
  using Runs = std::vector<std::pair<uint64_t, size_t>>;
  EXPECT_EQ(runs(VoxelBox::whole(kDims), 2), (Runs{{0, 13 * 11 * 7 * 2}}));
  EXPECT_EQ(runs({{0, 0, 2}, {13, 11, 4}}, 4), (Runs{{2 * 143 * 4, 2 * 143 * 4}}));
  EXPECT_EQ(runs({{0, 3, 2}, {13, 5, 4}}, 1),
            (Runs{{2 * 143 + 3 * 13, 26}, {3 * 143 + 3 * 13, 26}}));
  EXPECT_EQ(runs({{1, 3, 2}, {4, 5, 3}}, 2),
            (Runs{{(2 * 143 + 3 * 13 + 1) * 2, 6}, {(2 * 143 + 4 * 13 + 1) * 2, 6}}));
  // The last voxel of a row and the first of the next are contiguous too.
  EXPECT_EQ(runs({{12, 0, 0}, {13, 1, 1}}, 1), (Runs{{12, 1}}));
}

TEST_F(VolumeRegion, ABoxOutsideTheGridOrEmptyNamesTheFile) {
  write_nrrd(written_volume<int16_t>(), dir / "a.nrrd", false);
  write_nrrd(written_volume<int16_t>(), dir / "g.nrrd", true);
  write_metaimage(written_volume<int16_t>(), dir / "a.mha", true);
  write_nifti(written_volume<int16_t>(), dir / "a.nii", false);
  write_nifti(written_volume<int16_t>(), dir / "a.nii.gz", true);
  const VoxelBox bad[] = {
      {glm::ivec3(0), kDims + glm::ivec3(1, 0, 0)},  // one past x
      {glm::ivec3(0), kDims + glm::ivec3(0, 0, 1)},  // one past z
      {{-1, 0, 0}, {2, 2, 2}},                       // negative
      {{3, 3, 3}, {3, 5, 5}},                        // empty along x
      {{3, 3, 3}, {5, 5, 2}},                        // inverted along z
  };
  for (const char* name : {"a.nrrd", "g.nrrd", "a.mha", "a.nii", "a.nii.gz"})
    for (const VoxelBox& box : bad)
      expect_error([&] { read_volume_region(dir / name, box); },
                   {name, "voxel box", "empty or leaves the 13x11x7 grid"});
}

// Cuts `file` to `size` bytes.
void truncate_to(const fs::path& file, uintmax_t size) {
  fs::resize_file(file, size);
}

TEST_F(VolumeRegion, DataTruncatedInsideTheBoxIsAnErrorNamingTheFile) {
  const VoxelBox box{{2, 3, 1}, {9, 8, 5}};
  const size_t voxels = static_cast<size_t>(kDims.x) * kDims.y * kDims.z;
  // Uncompressed: the file ends inside the box's rows (slice 3 of 1..4).
  write_nrrd(written_volume<int16_t>(), dir / "a.nrrd", false);
  truncate_to(dir / "a.nrrd", fs::file_size(dir / "a.nrrd") - voxels * 2 * 4 / 7);
  expect_error([&] { read_volume_region(dir / "a.nrrd", box); },
               {"a.nrrd", "expected 2002 bytes of voxel data"});
  test::write_bytes(dir / "d.mhd", mhd_header("MET_USHORT", "ElementDataFile = d.raw\n"));
  test::write_bytes(dir / "d.raw", voxel_bytes<uint16_t>(kDims).substr(0, 1000));
  expect_error([&] { read_volume_region(dir / "d.mhd", box); }, {"d.raw", "d.mhd", "expected"});
  write_nifti(written_volume<int16_t>(), dir / "a.nii", false);
  truncate_to(dir / "a.nii", 352 + 900);
  expect_error([&] { read_volume_region(dir / "a.nii", box); }, {"a.nii", "expected 2002 bytes"});

  // Compressed: the stream stops inside the box; and its end is missing after the box.
  const std::string data = voxel_bytes<int16_t>(kDims);
  const std::string head = nrrd_header("int16", "endian: little\nencoding: gzip\n\n");
  test::write_bytes(dir / "g.nrrd", head + gzipped(data.substr(0, 800)));
  expect_error([&] { read_volume_region(dir / "g.nrrd", box); }, {"g.nrrd", "found 800"});
  test::write_bytes(dir / "h.nrrd", head + gzipped(data.substr(0, 1900)));
  expect_error([&] { read_volume_region(dir / "h.nrrd", box); }, {"h.nrrd", "found 1900"});
  std::string cut = gzipped(data);
  cut.resize(cut.size() - 6);  // the checksum and length: the data is there, its end is not
  test::write_bytes(dir / "c.nrrd", head + cut);
  expect_error([&] { read_volume_region(dir / "c.nrrd", box); }, {"c.nrrd", "checksum"});
  test::write_bytes(dir / "m.mha", mhd_header("MET_SHORT",
                                              "CompressedData = True\n"
                                              "ElementDataFile = LOCAL\n") +
                                       gzipped(data.substr(0, 1000)));
  expect_error([&] { read_volume_region(dir / "m.mha", box); }, {"m.mha", "found 1000"});
  test::write_bytes(dir / "t.nii.gz",
                    gzipped(nifti_bytes(nifti_header(DT_INT16, 16), data.substr(0, 700))));
  expect_error([&] { read_volume_region(dir / "t.nii.gz", box); }, {"t.nii.gz", "expected 2002"});
}

TEST_F(VolumeRegion, HeaderErrorsAreTheWholeReadsErrors) {
  test::write_bytes(dir / "bad.nrrd", nrrd_header("int16", "encoding: raw\n\n"));
  expect_error([&] { read_volume_header(dir / "bad.nrrd"); },
               {"bad.nrrd", "missing field 'endian'"});
  expect_error(
      [&] {
        read_volume_region(dir / "bad.nrrd", {glm::ivec3(0), glm::ivec3(1)});
      },
      {"bad.nrrd", "missing field 'endian'"});
  test::write_bytes(dir / "bad.mha", "ObjectType = Image\nNDims = 4\nElementDataFile = LOCAL\n");
  expect_error([&] { read_volume_header(dir / "bad.mha"); }, {"bad.mha", "NDims"});
  nifti_1_header h = nifti_header(DT_INT16, 16);
  h.dim[0] = 2;
  test::write_bytes(dir / "bad.nii", nifti_bytes(h, voxel_bytes<int16_t>(kDims)));
  expect_error([&] { read_volume_header(dir / "bad.nii"); }, {"bad.nii", "2 dimensions"});
  // The header alone does not need the data file; the region read does.
  test::write_bytes(dir / "nodata.nhdr",
                    nrrd_header("uint8", "encoding: raw\ndata file: no.raw\n"));
  EXPECT_EQ(read_volume_header(dir / "nodata.nhdr").dims, kDims);
  expect_error(
      [&] {
        read_volume_region(dir / "nodata.nhdr", {glm::ivec3(0), glm::ivec3(1)});
      },
      {"no.raw", "no such file"});
  expect_error([&] { read_volume_header(dir / "none.nii"); }, {"none.nii", "no such file"});
}

TEST(PhantomRegion, EveryPhantomsRegionIsItsCrop) {
  for (const std::string& name : phantom_names()) {
    const VolumeData whole = make_phantom(name, 16);
    const VolumeHeader h = phantom_header(name, 16);
    EXPECT_EQ(h.dims, whole.dims) << name;
    EXPECT_EQ(h.type, whole.type()) << name;
    EXPECT_EQ(h.index_to_world, whole.index_to_world) << name;
    for (const VoxelBox& box : boxes_for(whole.dims))
      expect_same(make_phantom_region(name, 16, box), crop(whole, box, name),
                  name + " " + box_text(box));
  }
}

TEST(PhantomRegion, BoxesAndNamesAreChecked) {
  const glm::ivec3 dims = phantom_header("cube", 8).dims;
  expect_error(
      [&] {
        make_phantom_region("cube", 8, {glm::ivec3(0), dims + 1});
      },
      {"phantom 'cube'", "leaves the 8x8x8 grid"});
  expect_error(
      [&] {
        make_phantom_region("cube", 8, {glm::ivec3(2), glm::ivec3(2)});
      },
      {"phantom 'cube'", "empty"});
  expect_error([&] { phantom_header("nothing", 8); }, {"unknown phantom 'nothing'"});
  expect_error(
      [&] {
        make_phantom_region("cube", 4, {glm::ivec3(0), glm::ivec3(1)});
      },
      {"size 4 is out of range"});
}

// The volumes of ../shared/data (skipped when it is absent): a middle box and a corner box.
TEST(VolumeRegionSharedData, RealFilesRegionReadsAreTheirCrops) {
  const fs::path data = test::shared_data();
  int found = 0;
  for (const char* name : {"FLAIR.nrrd", "FLAIR.nii.gz", "hippo.nii.gz", "mha.mha"}) {
    const fs::path file = data / name;
    if (!fs::exists(file)) continue;
    ++found;
    const glm::ivec3 d = read_volume_header(file).dims;
    check_file(file, {{d / 4, d - d / 4}, {glm::ivec3(0), glm::max(d / 3, 1)}, {d - 1, d}});
  }
  if (found == 0) GTEST_SKIP() << "no volumes in " << data.string();
}

}  // namespace
}  // namespace imx
