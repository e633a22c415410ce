// read_volume_region's peak memory: a box of a 32 MB volume must not cost the whole volume.
// A program of its own because ru_maxrss is the process's high-water mark: nothing that reads
// a whole volume may run before these tests in the same process (ctest runs each test in a
// process of its own as well).
#include <sys/resource.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <zlib.h>

#include "../io/temp_dir.hpp"
#include "intermix/io.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;

constexpr int kSize = 256;  // 256^3 uint16: 32 MiB of voxels
constexpr int64_t kWholeKiB = int64_t{kSize} * kSize * kSize * 2 / 1024;
// A 256x256x16 box is 2 MiB; the readers' buffers add at most about 1 MiB.
constexpr int64_t kBoundKiB = 8 * 1024;

int64_t max_rss_kib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;  // KiB on Linux
}

uint16_t value(int i, int j, int k) {
  return static_cast<uint16_t>(i * 3 + j * 257 + k * 11);
}

std::string header(const std::string& encoding) {
  return "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 256 256 256\nendian: little\nencoding: " +
         encoding + "\n\n";
}

// One slice's bytes, so that writing the file never holds the whole volume.
std::vector<uint16_t> slice(int k) {
  std::vector<uint16_t> s(static_cast<size_t>(kSize) * kSize);
  for (int j = 0; j < kSize; ++j)
    for (int i = 0; i < kSize; ++i) s[static_cast<size_t>(j) * kSize + i] = value(i, j, k);
  return s;
}

fs::path write_raw(const test::TempDir& dir) {
  const fs::path file = dir / "big.nrrd";
  std::ofstream out(file, std::ios::binary);
  out << header("raw");
  for (int k = 0; k < kSize; ++k) {
    const std::vector<uint16_t> s = slice(k);
    out.write(reinterpret_cast<const char*>(s.data()),
              static_cast<std::streamsize>(s.size() * sizeof(uint16_t)));
  }
  return file;
}

fs::path write_gzip(const test::TempDir& dir) {
  const fs::path file = dir / "big-gz.nrrd";
  {
    std::ofstream out(file, std::ios::binary);
    out << header("gzip");
  }
  // "ab": one gzip member appended after the header, fed slice by slice.
  gzFile gz = gzopen(file.c_str(), "ab1");
  for (int k = 0; k < kSize; ++k) {
    const std::vector<uint16_t> s = slice(k);
    gzwrite(gz, s.data(), static_cast<unsigned>(s.size() * sizeof(uint16_t)));
  }
  gzclose(gz);
  return file;
}

// Reads slices [40, 56) and checks the values and the growth of the peak memory.
void check_region(const fs::path& file) {
  const VoxelBox box{{0, 0, 40}, {kSize, kSize, 56}};
  const int64_t before = max_rss_kib();
  const VolumeData v = read_volume_region(file, box);
  const int64_t grown = max_rss_kib() - before;
  ASSERT_EQ(v.dims, glm::ivec3(kSize, kSize, 16));
  const auto& voxels = std::get<VoxelBuffer<uint16_t>>(v.voxels);
  for (int k : {0, 7, 15})
    for (int j : {0, 100, 255})
      for (int i : {0, 128, 255})
        ASSERT_EQ(voxels[(static_cast<size_t>(k) * kSize + j) * kSize + i], value(i, j, k + 40));
  EXPECT_LT(grown, kBoundKiB) << file << ": the peak memory grew by " << grown
                              << " KiB; the whole volume is " << kWholeKiB << " KiB";
}

TEST(RegionMemory, RawNrrdReadsOnlyTheBox) {
  test::TempDir dir;
  check_region(write_raw(dir));
}

TEST(RegionMemory, GzipNrrdKeepsOnlyTheBox) {
  test::TempDir dir;
  check_region(write_gzip(dir));
}

// The measure itself: reading the whole does show (declared last: it raises the mark).
TEST(RegionMemory, AWholeReadDoesShow) {
  test::TempDir dir;
  const fs::path file = write_raw(dir);
  const int64_t before = max_rss_kib();
  const VolumeData v = read_volume(file);
  EXPECT_GT(max_rss_kib() - before, kWholeKiB * 9 / 10);
}

}  // namespace
}  // namespace imx
