// NIfTI-1 and NIfTI-2 (single files and .hdr/.img pairs), Analyze 7.5 pairs and 4-D files read
// as frames, each against what nibabel reads from the same file; then the refusals (bad magic,
// missing halves of a pair, truncation, corrupt gzip, huge dims) and write_nifti_frames.
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "nibabel_reference.hpp"
#include "pattern_volume.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::expect_equals_reference;
using test::expect_error;
using test::NibabelImage;
using test::read_reference;
using test::TempDir;

// Every file of the suite, written by nibabel in one run (Python's start-up is most of the cost).
const char* kScript = R"PY(
import struct
rng = np.random.default_rng(31)
aff = np.array([[0.9, 0.1, 0.0, -20.5], [-0.2, 1.1, 0.3, 14.0], [0.0, -0.1, 2.5, -7.25],
                [0.0, 0.0, 0.0, 1.0]])
series = rng.integers(-3000, 3000, size=(5, 4, 3, 6)).astype(np.int16)

def timed(img, step, unit):
    img.header.set_xyzt_units('mm', unit)
    img.header.set_zooms(img.header.get_zooms()[:3] + (step,))
    return img

def save(img, name):
    nib.save(img, name)
    ref(name)

def patch(path, offset, fmt, *values):
    b = bytearray(open(path, 'rb').read())
    struct.pack_into(fmt, b, offset, *values)
    open(path, 'wb').write(b)

# 4-D NIfTI-1 time series: plain, gzipped, big-endian with ms units.
save(timed(nib.Nifti1Image(series, aff), 2.5, 'sec'), 't.nii')
save(timed(nib.Nifti1Image(series, aff), 2.5, 'sec'), 't.nii.gz')
save(timed(nib.Nifti1Image(series, aff, nib.Nifti1Header(endianness='>')), 250.0, 'msec'),
     'be.nii.gz')
# A qform alone (a rotation with a flipped k axis: qfac -1).
c, s, c2, s2 = np.cos(0.3), np.sin(0.3), np.cos(0.5), np.sin(0.5)
rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ np.array([[1, 0, 0], [0, c2, -s2], [0, s2, c2]])
qaff = np.eye(4)
qaff[:3, :3] = rot @ np.diag([1.5, 0.8, -2.0])
qaff[:3, 3] = [10.0, -20.0, 30.0]
img = nib.Nifti1Image(series[..., :2], None)
img.set_qform(qaff, 1)
img.set_sform(None, 0)
save(img, 'q.nii')
# Floats stored as uint8 with scl_slope/scl_inter chosen by nibabel.
img = nib.Nifti1Image(np.linspace(-100, 300, 5 * 4 * 3 * 2).reshape(5, 4, 3, 2), aff)
img.set_data_dtype(np.uint8)
save(img, 'scaled.nii.gz')
# Components along dim[5] (dim[4] is 1).
save(nib.Nifti1Image(rng.standard_normal((4, 3, 2, 1, 3)).astype(np.float32), aff), 'vec.nii')

# NIfTI-2: float64, a big-endian gzipped 4-D series, a pair.
f64 = rng.standard_normal((5, 4, 3)) * 100
save(nib.Nifti2Image(f64, aff), 'two.nii')
save(timed(nib.Nifti2Image(series, aff, nib.Nifti2Header(endianness='>')), 0.5, 'sec'),
     'two_be.nii.gz')
save(nib.Nifti2Pair(np.abs(series).astype(np.uint16), aff), 'two_pair.hdr')

# NIfTI-1 pairs, named by the .img, and gzipped (.hdr.gz with .img.gz).
save(nib.Nifti1Pair(series, aff), 'one_pair.img')
save(nib.Nifti1Pair(f64.astype(np.float32), aff), 'zpair.hdr.gz')

# Analyze 7.5: no orientation (nibabel: x flipped, centred), big-endian 4-D, SPM's origin and
# scale factor, and scaling by the calibrated range.
a = rng.integers(-500, 500, size=(5, 4, 3)).astype(np.int16)
save(nib.AnalyzeImage(a, np.diag([2.0, 3.0, 4.0, 1.0])), 'ana.hdr')
save(nib.AnalyzeImage(series, np.diag([1.5, 1.5, 3.0, 1.0]), nib.AnalyzeHeader(endianness='>')),
     'ana_be.hdr')
nib.save(nib.AnalyzeImage(a, np.diag([2.0, 3.0, 4.0, 1.0])), 'spm.hdr')
patch('spm.hdr', 253, '<3h', 2, 3, 1)
patch('spm.hdr', 112, '<2f', 0.5, 3.0)
ref('spm.hdr')
nib.save(nib.AnalyzeImage(a, np.diag([2.0, 3.0, 4.0, 1.0])), 'cal.hdr')
patch('cal.hdr', 112, '<f', 0.0)
patch('cal.hdr', 124, '<2f', 10.0, -10.0)
patch('cal.hdr', 140, '<2i', 200, 0)
ref('cal.hdr')
)PY";

class NiftiFamily : public test::NibabelFiles<&kScript> {
 protected:
  static void expect_frames_equal_nibabel(const std::string& name, const fs::path& read_as = {}) {
    const fs::path path = read_as.empty() ? file(name) : read_as;
    const NibabelImage ref = read_reference(file(name));
    const VolumeHeader header = read_volume_header(path);
    EXPECT_EQ(header.frames, ref.frames) << name;
    EXPECT_EQ(header.dims, ref.dims) << name;
    for (int k = 0; k < ref.frames; ++k) {
      const VolumeData v = read_volume(path, k);
      EXPECT_EQ(v.type(), header.type) << name;
      expect_equals_reference(v, ref, k, path.string());
    }
  }
};

TEST_F(NiftiFamily, TimeSeriesFramesEqualNibabelPlainGzipAndBigEndian) {
  for (const char* name : {"t.nii", "t.nii.gz", "be.nii.gz"}) expect_frames_equal_nibabel(name);
  // The frame times: pixdim[4] in xyzt_units' unit, as seconds.
  const VolumeHeader t = read_volume_header(file("t.nii"));
  ASSERT_EQ(t.frame_labels.size(), 6u);
  EXPECT_EQ(t.frame_labels[0].time_s, 0.0);
  EXPECT_DOUBLE_EQ(*t.frame_labels[3].time_s, 7.5);
  EXPECT_EQ(t.frame_labels[1].text, "t=2.5 s");
  const VolumeHeader be = read_volume_header(file("be.nii.gz"));
  ASSERT_EQ(be.frame_labels.size(), 6u);
  EXPECT_DOUBLE_EQ(*be.frame_labels[2].time_s, 0.5);  // 250 ms steps
}

TEST_F(NiftiFamily, RegionOfAFrameIsTheCropOfThatFrame) {
  const VoxelBox box{{1, 1, 0}, {4, 3, 2}};
  for (const char* name : {"t.nii", "t.nii.gz"}) {
    for (int k : {0, 4, 5}) {
      const VolumeData whole = read_volume(file(name), k);
      const VolumeData part = read_volume_region(file(name), box, k);
      const VolumeData crop_of = crop(whole, box, name);
      EXPECT_EQ(part.dims, crop_of.dims);
      EXPECT_TRUE(std::get<VoxelBuffer<int16_t>>(part.voxels) ==
                  std::get<VoxelBuffer<int16_t>>(crop_of.voxels))
          << name << " frame " << k;
    }
  }
}

TEST_F(NiftiFamily, QformScalingAndComponentsEqualNibabel) {
  expect_frames_equal_nibabel("q.nii");
  expect_frames_equal_nibabel("scaled.nii.gz");
  EXPECT_EQ(read_volume(file("scaled.nii.gz"), 1).type(), VoxelType::f32);
  expect_frames_equal_nibabel("vec.nii");
  // Components carry no time.
  EXPECT_TRUE(read_volume_header(file("vec.nii")).frame_labels.empty());
}

TEST_F(NiftiFamily, Nifti2SingleFilesAndPairsEqualNibabel) {
  expect_frames_equal_nibabel("two.nii");
  expect_frames_equal_nibabel("two_be.nii.gz");
  EXPECT_EQ(read_volume_header(file("two_be.nii.gz")).frame_labels.at(4).text, "t=2 s");
  expect_frames_equal_nibabel("two_pair.hdr");
  expect_frames_equal_nibabel("two_pair.hdr", file("two_pair.img"));  // named by its .img
}

TEST_F(NiftiFamily, Nifti1PairsEqualNibabelNamedByEitherFileAndGzipped) {
  expect_frames_equal_nibabel("one_pair.img");
  expect_frames_equal_nibabel("one_pair.img", file("one_pair.hdr"));
  expect_frames_equal_nibabel("zpair.hdr.gz");
  expect_frames_equal_nibabel("zpair.hdr.gz", file("zpair.img.gz"));
}

TEST_F(NiftiFamily, AnalyzePairsArePlacedAndScaledAsNibabelDoes) {
  expect_frames_equal_nibabel("ana.hdr");
  expect_frames_equal_nibabel("ana_be.hdr");
  expect_frames_equal_nibabel("spm.hdr");
  expect_frames_equal_nibabel("cal.hdr");
  // The convention itself, in LPS: x flipped in RAS is +x in LPS, y negated; centred.
  const VolumeData v = read_volume(file("ana.hdr"));
  EXPECT_EQ(glm::dvec3(v.index_to_world[0]), glm::dvec3(2.0, 0.0, 0.0));
  EXPECT_EQ(glm::dvec3(v.index_to_world[1]), glm::dvec3(0.0, -3.0, 0.0));
  EXPECT_EQ(glm::dvec3(v.index_to_world[3]), glm::dvec3(-4.0, 4.5, -4.0));
  EXPECT_EQ(read_volume(file("spm.hdr")).type(), VoxelType::f32);
}

TEST_F(NiftiFamily, AFrameOutOfRangeNamesTheFileAndTheCount) {
  expect_error([&] { read_volume(file("t.nii"), 6); }, {"t.nii", "frame 6", "6 frames (0 to 5)"});
  expect_error(
      [&] {
        read_volume_region(file("t.nii.gz"), VoxelBox{{0, 0, 0}, {1, 1, 1}}, -1);
      },
      {"t.nii.gz", "frame -1"});
  expect_error([&] { read_volume(file("two.nii"), 1); }, {"two.nii", "one frame"});
}

TEST_F(NiftiFamily, ABadMagicIsRefusedNotReadAsAnalyze) {
  const std::string good = test::read_bytes(file("t.nii"));
  TempDir dir;
  struct Case {
    const char* name;
    size_t at;
    std::string magic;
    std::vector<std::string> fragments;
  };
  const Case cases[] = {
      {"zero.nii",
       344,
       std::string(4, '\0'),
       {"zero.nii", "magic is '\\x00\\x00\\x00\\x00'", "n+1"}},
      {"typo.nii", 344, std::string("nX1\0", 4), {"typo.nii", "magic is 'nX1'", "Analyze"}},
      {"pair.nii", 344, std::string("ni1\0", 4), {"pair.nii", "'ni1'", ".hdr/.img pair"}},
  };
  for (const Case& c : cases) {
    std::string bytes = good;
    bytes.replace(c.at, c.magic.size(), c.magic);
    test::write_bytes(dir / c.name, bytes);
    const std::string message = expect_error([&] { read_volume(dir / c.name); }, {});
    for (const std::string& f : c.fragments)
      EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' missing from: " << message;
    expect_error([&] { read_volume_header(dir / c.name); }, {c.name, "magic"});
  }
  // NIfTI-2: the magic, and the \r\n\032\n check after it.
  const std::string two = test::read_bytes(file("two.nii"));
  std::string bad = two;
  bad.replace(4, 4, std::string("n+1\0", 4));
  test::write_bytes(dir / "two_magic.nii", bad);
  expect_error([&] { read_volume(dir / "two_magic.nii"); }, {"two_magic.nii", "'n+1'", "NIfTI-2"});
  bad = two;
  bad.replace(8, 4, std::string("\n\n\032\n", 4));
  test::write_bytes(dir / "two_eol.nii", bad);
  expect_error([&] { read_volume(dir / "two_eol.nii"); }, {"two_eol.nii", "bytes 8-11"});
}

TEST_F(NiftiFamily, AHalfOfAPairMissingOrAnSpmMatBesideItIsAClearError) {
  TempDir dir;
  fs::copy_file(file("ana.hdr"), dir / "lonely.hdr");
  expect_error([&] { read_volume(dir / "lonely.hdr"); }, {"lonely.hdr", "lonely.img", "missing"});
  fs::copy_file(file("ana.img"), dir / "orphan.img");
  expect_error([&] { read_volume_header(dir / "orphan.img"); },
               {"orphan.img", "orphan.hdr", "missing"});
  fs::copy_file(file("ana.hdr"), dir / "m.hdr");
  fs::copy_file(file("ana.img"), dir / "m.img");
  test::write_bytes(dir / "m.mat", "MATLAB 5.0 MAT-file");
  expect_error([&] { read_volume(dir / "m.hdr"); }, {"m.hdr", "m.mat", ".mat"});
  // A .hdr that says its voxels are in itself (n+1) is no pair's header.
  std::string h = test::read_bytes(file("one_pair.hdr"));
  h.replace(344, 4, std::string("n+1\0", 4));
  test::write_bytes(dir / "p.hdr", h);
  fs::copy_file(file("one_pair.img"), dir / "p.img");
  expect_error([&] { read_volume(dir / "p.hdr"); }, {"p.hdr", "'n+1'", "single .nii"});
}

TEST_F(NiftiFamily, TwoDimensionsBeyondTheThirdAreRefusedNamingTheDims) {
  std::string bytes = test::read_bytes(file("t.nii"));
  auto put_short = [&](size_t at, int16_t v) { std::memcpy(bytes.data() + at, &v, 2); };
  put_short(40, 5);       // dim[0]
  put_short(40 + 8, 3);   // dim[4]
  put_short(40 + 10, 2);  // dim[5]: 3 x 2 = the 6 volumes the file holds
  TempDir dir;
  test::write_bytes(dir / "two_axes.nii", bytes);
  expect_error([&] { read_volume(dir / "two_axes.nii"); },
               {"two_axes.nii", "5x4x3x3x2", "dim[4] and dim[5]"});
}

TEST_F(NiftiFamily, TruncatedOrCorruptSeriesAreRefusedForEveryFrame) {
  TempDir dir;
  const std::string raw = test::read_bytes(file("t.nii"));
  test::write_bytes(dir / "cut.nii", raw.substr(0, raw.size() - 10));
  // The last frame is short: frame 0 is refused too, the file being truncated.
  expect_error([&] { read_volume(dir / "cut.nii", 0); },
               {"cut.nii", "expected 720 bytes of voxel data (6 frames of 120)", "found 710"});
  const std::string gz = test::read_bytes(file("t.nii.gz"));
  test::write_bytes(dir / "cut.nii.gz", gz.substr(0, gz.size() - 30));
  expect_error([&] { read_volume(dir / "cut.nii.gz", 0); }, {"cut.nii.gz"});
  std::string flipped = gz;
  flipped[flipped.size() - 6] = static_cast<char>(flipped[flipped.size() - 6] ^ 0x5a);  // CRC
  test::write_bytes(dir / "crc.nii.gz", flipped);
  expect_error([&] { read_volume(dir / "crc.nii.gz", 1); }, {"crc.nii.gz", "corrupt gzip data"});
  expect_error(
      [&] {
        read_volume_region(dir / "crc.nii.gz", VoxelBox{{0, 0, 0}, {1, 1, 1}}, 0);
      },
      {"crc.nii.gz", "corrupt gzip data"});
}

TEST_F(NiftiFamily, HugeNifti2DimsAndFrameCountsAreRefused) {
  const std::string two = test::read_bytes(file("two.nii"));
  TempDir dir;
  auto with = [&](const char* name, std::initializer_list<std::pair<int, int64_t>> dims) {
    std::string b = two;
    for (auto [d, v] : dims) std::memcpy(b.data() + 16 + 8 * d, &v, 8);
    test::write_bytes(dir / name, b);
    return dir / name;
  };
  expect_error(
      [&] {
        read_volume(with("wide.nii", {{1, int64_t{1} << 40}}));
      },
      {"wide.nii", "dim[1] is 1099511627776"});
  expect_error(
      [&] {
        read_volume(with("many.nii", {{1, 1 << 20}, {2, 1 << 20}}));
      },
      {"many.nii", "voxels"});
  // 2^22 * 2^21 * 2^21 voxels is 2^64: a 64-bit product wraps to 0.
  expect_error(
      [&] {
        read_volume(with("wraps.nii", {{1, 1 << 22}, {2, 1 << 21}, {3, 1 << 21}}));
      },
      {"wraps.nii", "voxels"});
  expect_error(
      [&] {
        read_volume_header(with("frames.nii", {{0, 4}, {4, 1 << 20}}));
      },
      {"frames.nii", "1048576 frames"});
  expect_error([&] { read_volume(with("neg.nii", {{2, -3}})); }, {"neg.nii", "dim[2] is -3"});
}

TEST_F(NiftiFamily, WriteNiftiFramesWritesWhatNibabelReadsAsA4dSeries) {
  TempDir dir;
  std::vector<VolumeData> frames;
  for (int k = 0; k < 3; ++k) {
    VolumeData f = test::pattern_volume<int16_t>({4, 3, 2});
    auto& voxels = std::get<VoxelBuffer<int16_t>>(f.voxels);
    int16_t* v = voxels.mutable_data();
    for (size_t i = 0; i < voxels.size(); ++i) v[i] = static_cast<int16_t>(v[i] + 100 * k);
    frames.push_back(std::move(f));
  }
  write_nifti_frames(frames, dir / "w.nii.gz", 1.5);
  write_nifti_frames(frames, dir / "w.nii", 0.0, false);
  for (const char* name : {"w.nii.gz", "w.nii"}) {
    const VolumeHeader h = read_volume_header(dir / name);
    EXPECT_EQ(h.frames, 3) << name;
    for (int k = 0; k < 3; ++k) {
      const VolumeData r = read_volume(dir / name, k);
      EXPECT_TRUE(std::get<VoxelBuffer<int16_t>>(r.voxels) ==
                  std::get<VoxelBuffer<int16_t>>(frames[k].voxels))
          << name << " frame " << k;
    }
  }
  EXPECT_EQ(read_volume_header(dir / "w.nii.gz").frame_labels.at(2).text, "t=3 s");
  EXPECT_TRUE(read_volume_header(dir / "w.nii").frame_labels.empty());  // no frame time given
  ASSERT_TRUE(test::run_nibabel(dir, R"PY(
img = nib.load('w.nii.gz')
assert img.shape == (4, 3, 2, 3), img.shape
assert abs(img.header.get_zooms()[3] - 1.5) < 1e-6, img.header.get_zooms()
assert img.header.get_xyzt_units() == ('mm', 'sec'), img.header.get_xyzt_units()
ref('w.nii.gz')
)PY"));
  const NibabelImage ref = read_reference(dir / "w.nii.gz");
  for (int k = 0; k < 3; ++k) expect_equals_reference(frames[k], ref, k, "w.nii.gz");
  EXPECT_EQ(dir.entries().size(), 5u) << "no temporary files may remain";  // + make.py/.log, .ref
}

TEST(NiftiFramesWriter, RefusesFramesThatDoNotShareOneGrid) {
  TempDir dir;
  const VolumeData a = test::pattern_volume<int16_t>({4, 3, 2});
  VolumeData moved = a;
  moved.index_to_world[3].x += 1.0;
  const VolumeData other_type = test::pattern_volume<float>({4, 3, 2});
  const VolumeData other_dims = test::pattern_volume<int16_t>({4, 3, 3});
  expect_error([&] { write_nifti_frames({}, dir / "e.nii.gz"); }, {"e.nii.gz", "no frames"});
  expect_error(
      [&] {
        write_nifti_frames({a, other_dims}, dir / "d.nii.gz");
      },
      {"d.nii.gz", "frame 1", "4x3x3"});
  expect_error(
      [&] {
        write_nifti_frames({a, a, other_type}, dir / "t.nii.gz");
      },
      {"t.nii.gz", "frame 2", "float32"});
  expect_error(
      [&] {
        write_nifti_frames({a, moved}, dir / "m.nii.gz");
      },
      {"m.nii.gz", "frame 1", "placed"});
  expect_error([&] { write_nifti_frames({a}, dir / "s.nii.gz", -1.0); }, {"s.nii.gz", "-1"});
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
}  // namespace imx
