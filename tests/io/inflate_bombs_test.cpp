// Decompression bombs against the memory budget (issue 48, item 2): every container that
// inflates charges what it inflates and decodes to the budget before allocating it, counts a
// block shared by several arrays once per array, and refuses compressed voxel data whose claim
// the budget cannot hold whole before reading any of it, naming the file, the claim and the
// budget. Each file here is a few KB that claims tens of MB: no test allocates more.
#include <bzlib.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "encodings.hpp"
#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "peak_growth.hpp"
#include "temp_dir.hpp"
#include "volume_bytes.hpp"

namespace imx {
namespace {

using test::expect_error;
using test::PeakGrowth;
using test::TempDir;
using test::write_bytes;

// Restores the default limits when a test ends, whatever it set.
struct LimitsGuard {
  ~LimitsGuard() { set_input_limits({}); }
};

constexpr uint64_t kMiB = uint64_t{1} << 20;

// A .vtp of `points` float32 points and one triangle whose <Points> and `arrays` point-data
// arrays all name the one compressed block at offset 0 of the appended data: 12 bytes a point
// of zeros, a few KB compressed.
std::string shared_block_vtp(uint32_t points, int arrays) {
  const std::string block = test::zlib_compressed(std::string(size_t{points} * 12, '\0'));
  std::string appended;
  for (uint32_t v : {1u, points * 12, 0u, static_cast<uint32_t>(block.size())})
    appended.append(reinterpret_cast<const char*>(&v), 4);
  appended += block;
  std::string data;
  for (int i = 0; i < arrays; ++i)
    data += fmt::format(
        "<DataArray type=\"Float32\" Name=\"a{}\" NumberOfComponents=\"3\" format=\"appended\" "
        "offset=\"0\"/>",
        i);
  return fmt::format(
             "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" "
             "byte_order=\"LittleEndian\" header_type=\"UInt32\" "
             "compressor=\"vtkZLibDataCompressor\">\n<PolyData><Piece NumberOfPoints=\"{}\" "
             "NumberOfPolys=\"1\">\n<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" "
             "format=\"appended\" offset=\"0\"/></Points>\n<Polys><DataArray type=\"Int32\" "
             "Name=\"connectivity\" format=\"ascii\">0 1 2</DataArray><DataArray type=\"Int32\" "
             "Name=\"offsets\" format=\"ascii\">3</DataArray></Polys>\n<PointData>{}</PointData>"
             "\n</Piece></PolyData>\n<AppendedData encoding=\"raw\">\n_",
             points, data) +
         appended + "\n</AppendedData>\n</VTKFile>\n";
}

TEST(InflateBombs, VtpArraysSharingOneCompressedBlockAreChargedOncePerArray) {
  // The case: a 101 KB .vtp whose arrays all name one block reached 5.8 GB under
  // --max-memory 1G; each array was held to the budget alone. Here 16 arrays of 256 Ki points
  // keep 16 x 6 MiB of values from a 3 KB block, under a 40 MiB budget.
  LimitsGuard guard;
  TempDir dir;
  constexpr uint32_t kPoints = 256 * 1024;
  write_bytes(dir / "shared.vtp", shared_block_vtp(kPoints, 16));
  write_bytes(dir / "two.vtp", shared_block_vtp(kPoints, 2));
  ASSERT_LT(std::filesystem::file_size(dir / "shared.vtp"), 16 * 1024u);
  set_input_limits({40 * kMiB, false});
  {
    const PeakGrowth peak;
    expect_error([&] { read_mesh_file(dir / "shared.vtp"); },
                 {"shared.vtp", "data array 'a", "claims", "this file claimed before",
                  "memory budget of 40.0 MiB"});
    EXPECT_LT(peak.mib(), 48 + test::kSanitizerSlackMiB)
        << "the refused file's arrays were held past the budget";
  }
  // Two such arrays fit: the charge is what is held, not every byte ever decoded.
  const MeshFile two = read_mesh_file(dir / "two.vtp");
  EXPECT_EQ(two.point_data.size(), 2u);
  EXPECT_EQ(two.mesh.triangles.size(), 1u);
}

TEST(InflateBombs, AVtpBlockThatInflatesPastItsClaimIsRefused) {
  // The block header says 12 bytes a point; the block holds twice that.
  TempDir dir;
  std::string file = shared_block_vtp(1024, 0);
  const std::string small = test::zlib_compressed(std::string(1024 * 12, '\0'));
  const std::string large = test::zlib_compressed(std::string(1024 * 24, '\0'));
  const size_t at = file.find(small);
  ASSERT_NE(at, std::string::npos);
  file.replace(at, small.size(), large);
  const uint32_t size = static_cast<uint32_t>(large.size());
  file.replace(at - 4, 4, reinterpret_cast<const char*>(&size), 4);
  write_bytes(dir / "past.vtp", file);
  expect_error([&] { read_mesh_file(dir / "past.vtp"); },
               {"past.vtp", "(Points)", "compressed block 0",
                "decompresses to more than the 12288 bytes expected"});
}

// 128^3 uint16 zeros: 4 MiB claimed, some KB stored.
VolumeData zeros_volume() {
  VolumeData v;
  v.dims = glm::ivec3(128);
  v.voxels = std::vector<uint16_t>(size_t{128} * 128 * 128, 0);
  return v;
}

// `file` under a 4 MiB budget: half of it, what one volume read whole may take, is less than the
// 4 MiB it claims, and its data is compressed, so even an 8^3 box of it is refused.
void expect_claim_refused(const std::filesystem::path& file, const std::string& data) {
  LimitsGuard guard;
  set_input_limits({4 * kMiB, false});
  const PeakGrowth peak;
  const VoxelBox box{{0, 0, 0}, {8, 8, 8}};
  for (auto read : {+[](const std::filesystem::path& f) { read_volume(f); },
                    +[](const std::filesystem::path& f) {
                      read_volume_region(f, {{0, 0, 0}, {8, 8, 8}});
                    }}) {
    const std::string message =
        expect_error([&] { read(file); }, {file.filename().string(), data + " claims 4.0 MiB",
                                           "half the memory budget of 4.0 MiB", "bricks"});
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_LT(peak.mib(), 4 + test::kSanitizerSlackMiB);
  // Within the budget the same file reads, whole and in part.
  set_input_limits({16 * kMiB, false});
  EXPECT_EQ(read_volume_region(file, box).dims, glm::ivec3(8));
}

TEST(InflateBombs, CompressedVolumesClaimingMoreThanTheBudgetAreRefusedBeforeReading) {
  // The case: an 8 MB .nii.gz claiming 8 GiB passed the default budget and was read
  // brick by brick, inflating the whole stream for each brick. Compressed data has no bricks:
  // its claim must be one the budget holds whole.
  TempDir dir;
  const VolumeData v = zeros_volume();
  write_volume(v, dir / "z.nii.gz");
  write_volume(v, dir / "z.nrrd", true);
  write_volume(v, dir / "z.mha", true);
  ASSERT_LT(std::filesystem::file_size(dir / "z.nii.gz"), 64 * 1024u);
  expect_claim_refused(dir / "z.nii.gz", "gzip voxel data");
  expect_claim_refused(dir / "z.nrrd", "gzip voxel data");
  expect_claim_refused(dir / "z.mha", "compressed voxel data");

  // NRRD's bzip2 encoding, compressed here with libbz2.
  std::string zeros(4 * kMiB, '\0');
  std::string packed(64 * 1024, '\0');
  auto packed_size = static_cast<unsigned>(packed.size());
  ASSERT_EQ(BZ2_bzBuffToBuffCompress(packed.data(), &packed_size, zeros.data(),
                                     static_cast<unsigned>(zeros.size()), 9, 0, 0),
            BZ_OK);
  packed.resize(packed_size);
  write_bytes(dir / "bz.nrrd",
              "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 128 128 128\nendian: little\n"
              "encoding: bzip2\n\n" +
                  packed);
  expect_claim_refused(dir / "bz.nrrd", "bzip2 voxel data");
}

TEST(InflateBombs, AFrameOfCompressedFourDDataIsClaimedByItself) {
  // 8 frames of 64^3 uint16 (512 KiB each, 4 MiB in all) under a 2 MiB budget: one frame is
  // what a whole read keeps, so a frame reads though all of them would not fit.
  LimitsGuard guard;
  TempDir dir;
  const std::string frame(size_t{64} * 64 * 64 * 2, '\0');
  std::string frames;
  for (int f = 0; f < 8; ++f) frames += frame;
  write_bytes(dir / "dwi.nrrd",
              "NRRD0004\ntype: uint16\ndimension: 4\nsizes: 64 64 64 8\nkinds: domain domain "
              "domain list\nspace: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) "
              "(0,0,1) none\nendian: little\nencoding: gzip\n\n" +
                  test::gzipped(frames));
  VolumeData one;
  one.dims = glm::ivec3(64);
  one.voxels = std::vector<uint16_t>(size_t{64} * 64 * 64, 0);
  write_nifti_frames(std::vector<VolumeData>(8, one), dir / "bold.nii.gz");
  set_input_limits({2 * kMiB, false});
  for (const char* name : {"dwi.nrrd", "bold.nii.gz"}) {
    SCOPED_TRACE(name);
    EXPECT_EQ(read_volume(dir / name, 5).dims, glm::ivec3(64));
  }
  set_input_limits({kMiB / 2, false});  // half of it is less than a frame
  expect_error([&] { read_volume(dir / "dwi.nrrd", 5); },
               {"dwi.nrrd", "gzip voxel data of one frame claims 512.0 KiB",
                "half the memory budget of 512.0 KiB"});
}

TEST(InflateBombs, ACompressedGridOfMoreVoxelsThanOneVolumeHoldsIsRefusedNotBricked) {
  // 2048^3 uint8 under the default budget: more voxels than a volume in memory holds, which an
  // uncompressed file renders in bricks. Only the header is written: nothing is inflated.
  TempDir dir;
  const std::string header =
      "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2048 2048 2048\nencoding: gzip\n\n";
  write_bytes(dir / "huge.nrrd", header + std::string(8 << 20, '\0'));
  expect_error(
      [&] {
        read_volume_region(dir / "huge.nrrd", {{0, 0, 0}, {8, 8, 8}});
      },
      {"huge.nrrd", "gzip voxel data claims 8.0 GiB", "2^31 voxels", "memory budget of", "bricks"});
}

}  // namespace
}  // namespace imx
