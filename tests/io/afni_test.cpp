// AFNI BRIK/HEAD: datasets written by this test's own Python writer and the shared real ones,
// read against nibabel.brikhead (voxels, affine in LPS, sub-brick labels and TR), then the
// refusals of lying headers, truncated BRIKs and unsupported types.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "io/volume/afni.hpp"
#include "nibabel_reference.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using detail::read_afni;
using detail::read_afni_header;
using detail::read_afni_region;
using test::expect_equals_reference;
using test::expect_error;
using test::NibabelImage;
using test::read_reference;

// afni() writes a dataset as AFNI lays it out (README.attributes); info() writes what nibabel's
// header says beside ref()'s voxels: the labels, one a line, then the fourth zoom (the TR).
const char* kWriter = R"PY(
import gzip

def info(path, out):
    h = nib.load(path).header
    with open(out + '.info', 'w') as f:
        for lab in (h.get_volume_labels() or []):
            f.write(lab + '\n')
        f.write('zoom %r\n' % float(h.get_zooms()[3]))

def cardinal(orient, origin, delta):
    m = np.zeros((3, 4))
    for a in range(3):
        m[orient[a] // 2, a] = delta[a]
        m[orient[a] // 2, 3] = origin[a]
    return m

def afni(prefix, data, btype=1, order='LSB_FIRST', facs=None, labels=None, real=True,
         orient=(0, 3, 4), origin=(-10.5, -20.25, -30.0), delta=(2.0, 3.0, 4.0), matrix=None,
         taxis=None, gz=False, dims=None, types=None, cut=0, pad=0):
    nx, ny, nz, nt = data.shape
    blocks = []
    def s(name, text):
        blocks.append("type = string-attribute\nname = %s\ncount = %d\n'%s~\n" % (name, len(text) + 1, text))
    def i(name, vals):
        blocks.append("type = integer-attribute\nname = %s\ncount = %d\n %s\n" % (name, len(vals), ' '.join('%d' % v for v in vals)))
    def f(name, vals):
        blocks.append("type  = float-attribute\nname  = %s\ncount = %d\n %s\n" % (name, len(vals), ' '.join(repr(float(v)) for v in vals)))
    s('TYPESTRING', '3DIM_HEAD_ANAT')
    i('ORIENT_SPECIFIC', orient)
    f('ORIGIN', origin)
    f('DELTA', delta)
    if real:
        m = cardinal(orient, origin, delta) if matrix is None else np.asarray(matrix)
        f('IJK_TO_DICOM_REAL', m.ravel())
    i('DATASET_RANK', [3, nt, 0, 0, 0, 0, 0, 0])
    i('DATASET_DIMENSIONS', list(dims or (nx, ny, nz)) + [0, 0])
    i('BRICK_TYPES', types or [btype] * nt)
    if facs is not None:
        f('BRICK_FLOAT_FACS', facs)
    if taxis is not None:
        i('TAXIS_NUMS', [nt, nz, taxis[1], -999, -999, -999, -999, -999])
        f('TAXIS_FLOATS', [0, taxis[0], 0, 0, 0, -999999, -999999, -999999])
    s('BYTEORDER_STRING', order)
    if labels is not None:
        s('BRICK_LABS', '~'.join(labels))
    open(prefix + '.HEAD', 'w').write('\n' + '\n'.join(blocks))
    kind = {0: 'u1', 1: 'i2', 3: 'f4', 5: 'c8'}[btype]
    raw = data.astype(('>' if order == 'MSB_FIRST' else '<') + kind).ravel(order='F').tobytes()
    raw = raw[:len(raw) - cut] + b'\0' * pad
    if gz:
        open(prefix + '.BRIK.gz', 'wb').write(gzip.compress(raw))
    else:
        open(prefix + '.BRIK', 'wb').write(raw)
)PY";

const char* kScript = R"PY(
rng = np.random.default_rng(11)
c, s = np.cos(0.3), np.sin(0.3)
oblique = [[2.0 * c, -3.0 * s, 0.0, 12.5], [2.0 * s, 3.0 * c, 0.0, -7.0], [0.0, 0.0, 4.0, 3.25]]
# Big-endian shorts, three labelled sub-bricks, one factor 0 (meaning 1), TR 2.5 s, oblique.
d = rng.integers(-3000, 3000, size=(5, 4, 3, 3))
afni('scaled+orig', d, order='MSB_FIRST', facs=[0.5, 0.0, 2.25], labels=['first', 'second', 'third'],
     matrix=oblique, taxis=(2.5, 77002))
ref('scaled+orig.HEAD'); info('scaled+orig.HEAD', 'scaled+orig.HEAD')
# Floats in a BRIK.gz, a +tlrc view, TR in ms.
afni('gz+tlrc', rng.standard_normal((4, 6, 5, 2)) * 40, btype=3, gz=True, taxis=(1500.0, 77001),
     orient=(1, 2, 5), origin=(30.0, -40.0, 50.0), delta=(-1.5, 2.0, -2.5))
ref('gz+tlrc.HEAD'); info('gz+tlrc.HEAD', 'gz+tlrc.HEAD')
# Bytes in +acpc, unscaled (factors all 0); its twin without IJK_TO_DICOM_REAL.
b = rng.integers(0, 256, size=(6, 5, 4, 1))
afni('bytes+acpc', b, btype=0, facs=[0.0], orient=(1, 2, 5), origin=(30.0, -40.0, 50.0),
     delta=(-1.5, 2.0, -2.5))
ref('bytes+acpc.HEAD')
afni('noreal+acpc', b, btype=0, real=False, orient=(1, 2, 5), origin=(30.0, -40.0, 50.0),
     delta=(-1.5, 2.0, -2.5))
# Lies and refusals.
small = rng.integers(0, 100, size=(4, 3, 2, 2))
afni('truncated+orig', small, cut=3)
afni('long+orig', small, pad=2)
afni('dimslie+orig', small, dims=(4, 3, 3))
afni('gzshort+orig', small, gz=True, cut=2)
afni('gzlong+orig', small, gz=True, pad=1)
afni('mixed+orig', small, types=[1, 3])
afni('complex+orig', small.astype(np.complex64), btype=5)
afni('double+orig', small, btype=3, types=[4, 4])
afni('order+orig', small, order='MIDDLE_FIRST')
)PY";

std::string full_script(const char* body) {
  return std::string(kWriter) + body;
}

// NibabelFiles runs one script; the writer is prepended to it here.
const std::string kAll = full_script(kScript);
const char* const kAllText = kAll.c_str();

class AfniFiles : public test::NibabelFiles<&kAllText> {
 protected:
  // The labels and TR that nibabel's header gives, as info() wrote them.
  static std::pair<std::vector<std::string>, double> nibabel_info(const std::string& name) {
    std::ifstream in(file(name + ".info"));
    std::vector<std::string> labels;
    double zoom = 0.0;
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("zoom ", 0) == 0)
        zoom = std::stod(line.substr(5));
      else
        labels.push_back(line);
    }
    return {labels, zoom};
  }
  static void expect_every_frame_equal(const std::string& name, VoxelType type) {
    const NibabelImage r = read_reference(file(name));
    const VolumeHeader h = read_afni_header(file(name));
    ASSERT_EQ(h.frames, r.frames) << name;
    EXPECT_EQ(h.dims, r.dims) << name;
    EXPECT_EQ(h.type, type) << name;
    for (int f = 0; f < r.frames; ++f) {
      const VolumeData v = read_afni(file(name), f);
      EXPECT_EQ(v.type(), type) << name;
      expect_equals_reference(v, r, f, name);
    }
  }
};

TEST_F(AfniFiles, BigEndianScaledShortsEqualNibabelWithLabelsAndTimes) {
  expect_every_frame_equal("scaled+orig.HEAD", VoxelType::f32);
  const VolumeHeader h = read_afni_header(file("scaled+orig.HEAD"));
  const auto [labels, tr] = nibabel_info("scaled+orig.HEAD");
  ASSERT_EQ(h.frame_labels.size(), 3u);
  ASSERT_EQ(labels.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(h.frame_labels[k].text, labels[k]);
    ASSERT_TRUE(h.frame_labels[k].time_s.has_value());
    EXPECT_DOUBLE_EQ(*h.frame_labels[k].time_s, k * tr);  // TAXIS units: seconds
  }
}

TEST_F(AfniFiles, AGzippedFloatBrikInTlrcEqualsNibabelNamedEitherWay) {
  expect_every_frame_equal("gz+tlrc.HEAD", VoxelType::f32);
  const NibabelImage r = read_reference(file("gz+tlrc.HEAD"));
  expect_equals_reference(read_afni(file("gz+tlrc.BRIK.gz"), 1), r, 1, "gz+tlrc.BRIK.gz");
  const VolumeHeader h = read_afni_header(file("gz+tlrc.BRIK.gz"));
  const auto [labels, tr_ms] = nibabel_info("gz+tlrc.HEAD");
  EXPECT_TRUE(labels.empty());
  ASSERT_EQ(h.frame_labels.size(), 2u);
  EXPECT_DOUBLE_EQ(*h.frame_labels[1].time_s, tr_ms / 1000.0);  // TAXIS units: ms
}

TEST_F(AfniFiles, BytesStayBytesAndTheCardinalAxesPlaceAsIjkToDicomReal) {
  expect_every_frame_equal("bytes+acpc.HEAD", VoxelType::u8);
  const NibabelImage r = read_reference(file("bytes+acpc.HEAD"));
  // Without IJK_TO_DICOM_REAL (nibabel needs it), ORIENT_SPECIFIC, ORIGIN and DELTA place it.
  expect_equals_reference(read_afni(file("noreal+acpc.BRIK")), r, 0, "noreal+acpc");
}

TEST_F(AfniFiles, ARegionIsTheCropOfTheWhole) {
  for (const char* name : {"scaled+orig.HEAD", "gz+tlrc.HEAD"}) {
    const VoxelBox box{{1, 1, 1}, {3, 3, 3}};
    const VolumeData whole = read_afni(file(name), 1);
    const VolumeData part = read_afni_region(file(name), box, 1);
    const VolumeData want = crop(whole, box, name);
    ASSERT_EQ(part.dims, want.dims);
    EXPECT_EQ(part.index_to_world, want.index_to_world);
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) EXPECT_EQ(part.value_at(i, j, k), want.value_at(i, j, k));
  }
}

TEST_F(AfniFiles, ByteCountsThatDisagreeWithTheHeaderAreRefused) {
  expect_error([] { read_afni(file("truncated+orig.HEAD")); },
               {"truncated+orig.BRIK", "holds 93 bytes", "describes 96", "truncated"});
  expect_error([] { read_afni(file("long+orig.HEAD"), 1); }, {"holds 98 bytes", "describes 96"});
  expect_error([] { read_afni(file("dimslie+orig.HEAD")); }, {"describes 144", "4x3x3"});
  expect_error([] { read_afni(file("gzshort+orig.HEAD")); },
               {"gzshort+orig.BRIK.gz", "inflates to 94 bytes", "describes 96"});
  expect_error([] { read_afni(file("gzlong+orig.HEAD")); }, {"inflates to more than the 96"});
  expect_error([] { read_afni_header(file("gzshort+orig.BRIK")); },
               {"gzshort+orig.BRIK", "no such file"});
}

TEST_F(AfniFiles, UnsupportedTypesAndByteOrdersAreRefusedByName) {
  expect_error([] { read_afni(file("mixed+orig.HEAD")); }, {"BRICK_TYPES", "different types"});
  expect_error([] { read_afni(file("complex+orig.HEAD")); }, {"BRICK_TYPES 5", "complex"});
  expect_error([] { read_afni(file("double+orig.HEAD")); }, {"BRICK_TYPES 4", "double"});
  expect_error([] { read_afni(file("order+orig.HEAD")); }, {"BYTEORDER_STRING", "MIDDLE_FIRST"});
  expect_error([] { read_afni(file("scaled+orig.HEAD"), 3); }, {"frame 3", "3 frames"});
}

// Headers written by hand, around one valid dataset.
struct HandMade {
  test::TempDir dir;
  std::string head =
      "\ntype = integer-attribute\nname = DATASET_RANK\ncount = 2\n 3 1\n\n"
      "type = integer-attribute\nname = DATASET_DIMENSIONS\ncount = 3\n 2 2 1\n\n"
      "type = integer-attribute\nname = BRICK_TYPES\ncount = 1\n 0\n\n"
      "type = float-attribute\nname = IJK_TO_DICOM_REAL\ncount = 12\n"
      " 1 0 0 0 0 1 0 0 0 0 1 0\n";
  fs::path write(const std::string& text) {
    dir.write("h+orig.BRIK", std::string(4, '\x07'));
    return dir.write("h+orig.HEAD", text);
  }
};

TEST(AfniHead, CountsAndStringLengthsAreCheckedAndTheSniffFindsTheSyntax) {
  HandMade h;
  EXPECT_EQ(read_afni(h.write(h.head)).value_at(1, 1, 0), 7.0);
  EXPECT_TRUE(detail::is_afni_head(h.head));
  EXPECT_TRUE(detail::is_afni_head("type  = float-attribute\nname"));
  EXPECT_FALSE(detail::is_afni_head("mrtrix image\n"));
  EXPECT_FALSE(detail::is_afni_head("type = blob-attribute\n"));
  expect_error(
      [&] {
        read_afni(h.write(h.head + "\ntype = string-attribute\nname = X\ncount = 2\n'ab~\n"));
      },
      {"string attribute X", "count 2", "holds 3"});
  expect_error(
      [&] { read_afni(h.write(h.head + "\ntype = float-attribute\nname = Y\ncount = 3\n 1 2\n")); },
      {"attribute Y", "count 3", "holds 2 values"});
  expect_error(
      [&] {
        read_afni(
            h.write(h.head + "\ntype = float-attribute\nname = Z\ncount = 99999999999\n 1\n"));
      },
      {"attribute Z", "count '99999999999'"});
  expect_error(
      [&] {
        read_afni(h.write(h.head + "\ntype = integer-attribute\nname = W\ncount = 1\n 1.5\n"));
      },
      {"attribute W", "'1.5'", "integer"});
  std::string dims = h.head;
  dims.replace(dims.find(" 2 2 1"), 6, " 2 0 1");
  expect_error([&] { read_afni(h.write(dims)); }, {"DATASET_DIMENSIONS", "positive"});
  dims.replace(dims.find(" 2 0 1"), 6, " 99999 99999 9");
  expect_error([&] { read_afni(h.write(dims)); }, {"DATASET_DIMENSIONS", "more than"});
  std::string rank = h.head;
  rank.replace(rank.find(" 3 1\n"), 5, " 2 1\n");
  expect_error([&] { read_afni(h.write(rank)); }, {"DATASET_RANK[0] is 2"});
  expect_error([&] { read_afni(h.write("nothing here")); }, {"h+orig.HEAD"});
  expect_error([&] { read_afni(h.dir / "h+orig.nii"); }, {"not an AFNI dataset name"});
}

// The shared real datasets against nibabel: every voxel of every sub-brick, the affine (RAS in
// nibabel, LPS here), the labels and the TR.
TEST(AfniRealData, BothSharedDatasetsEqualNibabel) {
  SKIP_WITHOUT_SHARED_DATA(
      "neuro/volumes/example4d+orig.HEAD", "neuro/volumes/example4d+orig.BRIK.gz",
      "neuro/volumes/vr_base_min_outlier+orig.HEAD", "neuro/volumes/vr_base_min_outlier+orig.BRIK");
  if (!test::have_nibabel()) GTEST_SKIP() << "/usr/bin/python3 with nibabel is not available";
  test::TempDir dir;
  const fs::path four = test::shared_data("neuro/volumes/example4d+orig.HEAD");
  const fs::path three = test::shared_data("neuro/volumes/vr_base_min_outlier+orig.BRIK");
  std::ostringstream script;
  script << kWriter;
  // ref() writes path + '.ref'; the shared data is read-only, so nibabel reads it through links.
  for (const auto& [path, name] : {std::pair{four, "four"}, std::pair{three, "three"}}) {
    const fs::path stem = path.parent_path() / path.stem();
    for (const char* ext : {".HEAD", ".BRIK", ".BRIK.gz"})
      if (fs::exists(stem.string() + ext))
        fs::create_symlink(stem.string() + ext, dir / (std::string(name) + "+orig" + ext));
    script << "ref('" << name << "+orig.HEAD'); info('" << name << "+orig.HEAD', '" << name
           << "+orig.HEAD')\n";
  }
  ASSERT_TRUE(test::run_nibabel(dir, script.str()));
  for (const char* name : {"four+orig.HEAD", "three+orig.HEAD"}) {
    const NibabelImage r = read_reference(dir / name);
    const VolumeHeader h = read_afni_header(dir / name);
    ASSERT_EQ(h.frames, r.frames) << name;
    EXPECT_EQ(h.type, VoxelType::i16) << name;
    for (int f = 0; f < r.frames; ++f)
      expect_equals_reference(read_afni(dir / name, f), r, f, name);
    std::ifstream in(dir / (std::string(name) + ".info"));
    std::vector<std::string> labels;
    double tr = 0.0;
    for (std::string line; std::getline(in, line);)
      line.rfind("zoom ", 0) == 0 ? void(tr = std::stod(line.substr(5))) : labels.push_back(line);
    ASSERT_EQ(h.frame_labels.size(), labels.size()) << name;
    for (size_t k = 0; k < labels.size(); ++k) {
      EXPECT_EQ(h.frame_labels[k].text, labels[k]) << name;
      if (h.frames > 1) {
        EXPECT_DOUBLE_EQ(*h.frame_labels[k].time_s, k * tr) << name;
      }
    }
  }
  EXPECT_EQ(read_afni_header(four).frames, 3);
  // The same placement from the cardinal attributes when IJK_TO_DICOM_REAL is dropped.
  std::string head = test::read_bytes(four);
  const size_t at = head.find("name  = IJK_TO_DICOM_REAL");
  ASSERT_NE(at, std::string::npos);
  head.replace(at, 25, "name  = IJK_TO_DICOM_REAX");
  dir.write("cardinal+orig.HEAD", head);
  fs::create_symlink(four.parent_path() / "example4d+orig.BRIK.gz", dir / "cardinal+orig.BRIK.gz");
  EXPECT_EQ(read_afni_header(dir / "cardinal+orig.HEAD").index_to_world,
            read_afni_header(four).index_to_world);
}

}  // namespace
}  // namespace imx
