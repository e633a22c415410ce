// FreeSurfer MGH/MGZ: every voxel type, frames and the footer's TR against what nibabel reads
// (data and img.affine), then the refusals of headers built byte by byte.
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "nibabel_reference.hpp"
#include "temp_dir.hpp"
#include "volume_bytes.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::expect_equals_reference;
using test::expect_error;
using test::gzipped;
using test::NibabelImage;
using test::read_reference;
using test::TempDir;

const char* kScript = R"PY(
rng = np.random.default_rng(5)
c, s = np.cos(0.4), np.sin(0.4)
aff = np.array([[-0.9 * c, 0.0, 1.2 * s, 31.5], [0.0, 0.0, -1.1, 12.25], [-0.9 * s, 1.0, -1.2 * c,
                -8.0], [0.0, 0.0, 0.0, 1.0]])

def save(data, name, tr=None):
    img = nib.MGHImage(data, aff)
    if tr is not None:
        img.header.set_zooms(img.header.get_zooms()[:3] + (tr,))
    nib.save(img, name)
    ref(name)

# Every MGH type, odd and even dims (the centre voxel is dims / 2), plain and gzipped.
save(rng.integers(0, 256, size=(5, 4, 3)).astype(np.uint8), 'u8.mgz')
save(rng.integers(-100000, 100000, size=(4, 5, 6)).astype(np.int32), 'i32.mgh')
save(rng.standard_normal((3, 4, 5)).astype(np.float32) * 50, 'f32.mgz')
save(rng.integers(-3000, 3000, size=(6, 3, 4)).astype(np.int16), 'i16.mgh')
# Frames, with a TR of 2 s in the footer.
frames = rng.standard_normal((4, 3, 5, 3)).astype(np.float32)
save(frames, 'frames.mgh', tr=2000.0)
save(frames.astype(np.int16), 'frames.mgz', tr=2000.0)
# goodRASflag 0: nibabel ignores the direction fields and uses its default.
nib.save(nib.MGHImage(rng.integers(0, 9, size=(4, 3, 2)).astype(np.uint8), aff), 'nogood.mgh')
b = bytearray(open('nogood.mgh', 'rb').read())
b[28:30] = b'\x00\x00'
open('nogood.mgh', 'wb').write(b)
ref('nogood.mgh')
)PY";

class Mgh : public test::NibabelFiles<&kScript> {
 protected:
  static void expect_frames_equal_nibabel(const std::string& name, VoxelType type) {
    const NibabelImage ref = read_reference(file(name));
    const VolumeHeader header = read_volume_header(file(name));
    EXPECT_EQ(header.frames, ref.frames) << name;
    EXPECT_EQ(header.type, type) << name;
    for (int k = 0; k < ref.frames; ++k) {
      const VolumeData v = read_volume(file(name), k);
      EXPECT_EQ(v.type(), type) << name;
      expect_equals_reference(v, ref, k, name);
    }
  }
};

TEST_F(Mgh, EveryTypeEqualsNibabelsDataAndAffine) {
  expect_frames_equal_nibabel("u8.mgz", VoxelType::u8);
  expect_frames_equal_nibabel("i32.mgh", VoxelType::f32);
  expect_frames_equal_nibabel("f32.mgz", VoxelType::f32);
  expect_frames_equal_nibabel("i16.mgh", VoxelType::i16);
}

TEST_F(Mgh, FramesEqualNibabelAndTakeTheirTimesFromTheFootersTr) {
  expect_frames_equal_nibabel("frames.mgh", VoxelType::f32);
  expect_frames_equal_nibabel("frames.mgz", VoxelType::i16);
  for (const char* name : {"frames.mgh", "frames.mgz"}) {
    const VolumeHeader h = read_volume_header(file(name));
    ASSERT_EQ(h.frame_labels.size(), 3u) << name;
    EXPECT_DOUBLE_EQ(*h.frame_labels[2].time_s, 4.0) << name;
    EXPECT_EQ(h.frame_labels[1].text, "t=2 s") << name;
  }
  EXPECT_TRUE(read_volume_header(file("u8.mgz")).frame_labels.empty());
  expect_error([&] { read_volume(file("frames.mgz"), 3); },
               {"frames.mgz", "frame 3", "3 frames (0 to 2)"});
  // A region of a frame is that frame's crop.
  const VoxelBox box{{1, 0, 2}, {3, 2, 5}};
  for (const char* name : {"frames.mgh", "frames.mgz"}) {
    const VolumeData part = read_volume_region(file(name), box, 2);
    const VolumeData whole = crop(read_volume(file(name), 2), box, name);
    ASSERT_EQ(part.dims, whole.dims);
    for (int k = 0; k < part.dims.z; ++k)
      for (int j = 0; j < part.dims.y; ++j)
        for (int i = 0; i < part.dims.x; ++i)
          EXPECT_EQ(part.value_at(i, j, k), whole.value_at(i, j, k)) << name;
  }
}

TEST_F(Mgh, WithoutGoodRasTheDefaultDirectionsAreNibabels) {
  expect_frames_equal_nibabel("nogood.mgh", VoxelType::u8);
}

// ---- headers built byte by byte

void put_be(std::string& out, const void* value, size_t size) {
  const auto* p = static_cast<const char*>(value);
  for (size_t i = 0; i < size; ++i) out += p[size - 1 - i];
}
void put_i32(std::string& out, int32_t v) {
  put_be(out, &v, 4);
}
void put_f32(std::string& out, float v) {
  put_be(out, &v, 4);
}

struct MghFields {
  int32_t version = 1, width = 2, height = 2, depth = 2, frames = 1, type = 0;
  int16_t good_ras = 1;
  float mdc_x_a = 0.0f;
};

std::string mgh_bytes(const MghFields& f, const std::string& data) {
  std::string out;
  for (int32_t v : {f.version, f.width, f.height, f.depth, f.frames, f.type, 0}) put_i32(out, v);
  put_be(out, &f.good_ras, 2);
  for (float v : {1.0f, 1.0f, 1.0f}) put_f32(out, v);
  for (float v : {-1.0f, f.mdc_x_a, 0.0f, 0.0f, 0.0f, -1.0f, 0.0f, 1.0f, 0.0f}) put_f32(out, v);
  for (float v : {0.0f, 0.0f, 0.0f}) put_f32(out, v);
  out.resize(284, '\0');
  return out + data;
}

TEST(MghBytes, ABigEndianHeaderBuiltByHandReads) {
  TempDir dir;
  MghFields f;
  f.type = 4;  // short
  std::string data;
  for (int16_t v = 0; v < 8; ++v) {
    const auto s = static_cast<int16_t>(v * 300 - 1000);
    put_be(data, &s, 2);
  }
  test::write_bytes(dir / "s.mgh", mgh_bytes(f, data));
  test::write_bytes(dir / "s.mgz", gzipped(mgh_bytes(f, data)));
  for (const char* name : {"s.mgh", "s.mgz"}) {
    const VolumeData v = read_volume(dir / name);
    ASSERT_EQ(v.type(), VoxelType::i16) << name;
    EXPECT_EQ(v.value_at(1, 0, 0), -700.0) << name;
    EXPECT_EQ(v.value_at(1, 1, 1), 1100.0) << name;
    // Mdc x = L (RAS -1,0,0), y = I, z = A, unit voxels, and the centre voxel, dims / 2 =
    // (1,1,1), at c_ras 0: in LPS, x = (1,0,0), y = (0,0,-1), z = (0,-1,0).
    const glm::dvec3 centre = glm::dvec3(v.index_to_world * glm::dvec4(1.0, 1.0, 1.0, 1.0));
    EXPECT_NEAR(glm::length(centre), 0.0, 1e-12) << name;
    EXPECT_EQ(glm::dvec3(v.index_to_world[0]), glm::dvec3(1.0, 0.0, 0.0)) << name;
    EXPECT_EQ(glm::dvec3(v.index_to_world[1]), glm::dvec3(0.0, 0.0, -1.0)) << name;
    EXPECT_EQ(glm::dvec3(v.index_to_world[2]), glm::dvec3(0.0, -1.0, 0.0)) << name;
  }
}

TEST(MghBytes, BadHeadersTruncatedDataAndCorruptGzipAreRefusedNamingTheFile) {
  TempDir dir;
  auto refuse = [&](const char* name, const std::string& bytes,
                    std::initializer_list<std::string> fragments) {
    test::write_bytes(dir / name, bytes);
    std::vector<std::string> all = fragments;
    all.insert(all.begin(), name);
    const std::string message = expect_error([&] { read_volume(dir / name); }, {});
    for (const std::string& f : all)
      EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' missing from: " << message;
  };
  const std::string eight(8, '\x01');
  MghFields f;
  refuse("short.mgh", "\0\0\0\1", {"too short for an MGH header"});
  f.version = 2;
  refuse("version.mgh", mgh_bytes(f, eight), {"version is 2"});
  f = {};
  f.type = 2;
  refuse("type.mgh", mgh_bytes(f, eight), {"type 2 is not supported"});
  f = {};
  f.depth = 0;
  refuse("zero.mgh", mgh_bytes(f, eight), {"2x2x0", "positive"});
  f = {};
  f.width = f.height = f.depth = 30000;
  refuse("huge.mgz", gzipped(mgh_bytes(f, eight)), {"30000x30000x30000", "voxels"});
  f = {};
  // A product that overflows 64 bits back into range (fuzz_mgh found it looping for minutes).
  f.width = 738197504;
  f.height = 50331648;
  f.depth = 33554432;
  refuse("wraps.mgh", mgh_bytes(f, eight), {"738197504x50331648x33554432", "voxels"});
  f = {};
  f.frames = 1 << 20;
  refuse("frames.mgh", mgh_bytes(f, eight), {"1048576 frames"});
  f = {};
  f.mdc_x_a = std::numeric_limits<float>::quiet_NaN();
  refuse("nan.mgh", mgh_bytes(f, eight), {"x_a is nan"});
  f = {};
  f.type = 3;  // float: 32 bytes wanted
  refuse("cut.mgh", mgh_bytes(f, eight), {"expected 32 bytes of voxel data", "found 8"});
  f.frames = 2;
  refuse("cut2.mgh", mgh_bytes(f, std::string(40, '\0')),
         {"expected 64 bytes of voxel data (2 frames of 32)", "found 40"});
  refuse("cut.mgz", gzipped(mgh_bytes(f, std::string(40, '\0'))), {"expected 64 bytes"});
  std::string crc = gzipped(mgh_bytes(f, std::string(64, '\0')));
  crc[crc.size() - 6] = static_cast<char>(crc[crc.size() - 6] ^ 0x33);
  refuse("crc.mgz", crc, {"corrupt gzip data"});
  refuse("cutgz.mgz", gzipped(mgh_bytes(f, "")).substr(0, 20), {"corrupt or truncated gzip data"});
  expect_error([&] { read_volume_header(dir / "crc.mgz"); }, {"crc.mgz", "corrupt gzip data"});
}

TEST(MghBytes, TheUnknownExtensionMessageListsTheNewFormats) {
  TempDir dir;
  test::write_bytes(dir / "x.vtk", "x");
  expect_error([&] { read_volume(dir / "x.vtk"); }, {"'.vtk' is not a volume format", ".hdr", ".img", ".mgh", ".mgz", "Analyze"});
}

}  // namespace
}  // namespace imx
