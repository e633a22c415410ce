// MRtrix .mif / .mif.gz / .mih: images written by this test's own Python writer from the
// documented format, read against the values and placement the writer started from and, where
// MRtrix 3's mrconvert is installed, against what it converts them to (read by nibabel) voxel by
// voxel in world space; then the refusals of lying headers.
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_inverse.hpp>

#include "expect_error.hpp"
#include "io/volume/mrtrix.hpp"
#include "nibabel_reference.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using detail::read_mrtrix;
using detail::read_mrtrix_header;
using detail::read_mrtrix_region;
using test::expect_equals_reference;
using test::expect_error;
using test::NibabelImage;
using test::read_reference;

bool have_mrconvert() {
  static const bool ok = std::system("command -v mrconvert >/dev/null 2>&1") == 0;
  return ok;
}

// mif() writes an image as the format's documentation lays it out: the values of `data` (image
// axes, x first) stored in the order and directions `layout` gives. expect() writes the ref()
// file of what a reader must find: `data` itself, placed by the transform with its columns
// scaled by vox (MRtrix's default transform, the grid centred on 0, when there is none).
// convert() has mrconvert write a NIfTI of the image, which nibabel then reads (ref()).
const char* kScript = R"PY(
import gzip, shutil, subprocess
rng = np.random.default_rng(7)
c, s = np.cos(0.35), np.sin(0.35)
T = [[c, -s, 0.0, -20.5], [s, c, 0.0, 14.0], [0.0, 0.0, 1.0, -3.25]]
dtypes = {'Int8': 'i1', 'UInt8': 'u1', 'Int16LE': '<i2', 'UInt16LE': '<u2', 'Int16BE': '>i2',
          'Float32LE': '<f4', 'Float32BE': '>f4', 'Float64BE': '>f8', 'Int32LE': '<i4'}

def mif(name, data, layout, dtype='Float32LE', vox=(1.5, 2.0, 2.5), transform=T, scaling=None,
        sep=None, gz=False, extra='', cut=0, dims=None):
    signs = [e[0] == '-' for e in layout]
    ranks = [int(e.lstrip('+-')) for e in layout]
    arr = data
    for a in range(data.ndim):
        if signs[a]:
            arr = np.flip(arr, a)
    order = sorted(range(data.ndim), key=lambda a: ranks[a])
    raw = np.transpose(arr, order).ravel(order='F').astype(dtypes[dtype]).tobytes()
    raw = raw[:len(raw) - cut]
    head = 'mrtrix image\ndim: %s\nvox: %s\nlayout: %s\ndatatype: %s\n' % (
        ','.join(str(n) for n in (dims or data.shape)), ','.join(repr(v) for v in vox),
        ','.join(layout), dtype)
    if transform is not None:
        for row in transform:
            head += 'transform: ' + ','.join(repr(v) for v in row) + '\n'
    if scaling is not None:
        head += 'scaling: %r,%r\n' % scaling
    head += extra
    if sep is not None:
        open(name, 'w').write(head + 'file: %s 16\nEND\n' % sep)
        open(sep, 'wb').write(b'\7' * 16 + raw)
        return
    offset = len(head) + len('file: . 000000\nEND\n')
    offset += (4 - offset % 4) % 4
    body = (head + 'file: . %06d\nEND\n' % offset).encode()
    body += b'\0' * (offset - len(body)) + raw
    open(name, 'wb').write(gzip.compress(body) if gz else body)

def expect(name, data, vox=(1.5, 2.0, 2.5), transform=T, scaling=None):
    m = np.eye(4)
    if transform is None:
        m[:3, 3] = [-0.5 * (data.shape[a] - 1) * vox[a] for a in range(3)]
    else:
        m[:3, :] = np.asarray(transform)
    m[:3, :3] = m[:3, :3] * np.asarray(vox[:3])
    values = data.astype(np.float64)
    if scaling is not None:
        values = scaling[0] + scaling[1] * values
    frames = values.reshape(values.shape[:3] + (-1,), order='F')
    with open(name + '.ref', 'wb') as f:
        np.array([frames.shape[3]] + list(frames.shape[:3]), dtype='<i8').tofile(f)
        np.asarray(m, dtype='<f8').tofile(f)
        frames.ravel(order='F').astype('<f8').tofile(f)

def convert(name):
    if shutil.which('mrconvert'):
        subprocess.run(['mrconvert', '-quiet', '-force', name, name + '.nii'], check=True)
        ref(name + '.nii')

d3 = (rng.standard_normal((5, 4, 3)) * 30).astype(np.float32)
for tag, layout in [('p012', ['+0', '+1', '+2']), ('m0', ['-0', '+1', '+2']),
                    ('doc', ['+2', '-0', '-1']), ('p120', ['+1', '+2', '+0']),
                    ('m210', ['-2', '-1', '-0'])]:
    mif(tag + '.mif', d3, layout); expect(tag + '.mif', d3); convert(tag + '.mif')
mif('be.mif', d3, ['+0', '+1', '+2'], dtype='Float32BE'); expect('be.mif', d3); convert('be.mif')
d64 = rng.standard_normal((3, 4, 5)) * 1e3
mif('f64.mif', d64, ['-1', '+0', '+2'], dtype='Float64BE'); expect('f64.mif', d64.astype(np.float32))
convert('f64.mif')
i16 = rng.integers(-3000, 3000, size=(4, 5, 3))
mif('scaled.mif', i16, ['+0', '-1', '+2'], dtype='Int16BE', scaling=(-3.5, 0.25))
expect('scaled.mif', i16, scaling=(-3.5, 0.25)); convert('scaled.mif')
i8 = rng.integers(-128, 128, size=(3, 3, 2))
mif('i8.mif', i8, ['+0', '+1', '+2'], dtype='Int8'); expect('i8.mif', i8); convert('i8.mif')
u8 = rng.integers(0, 256, size=(4, 2, 3))
mif('sep.mih', u8, ['+1', '+0', '+2'], dtype='UInt8', sep='sep.dat'); expect('sep.mih', u8)
convert('sep.mih')
d4 = rng.integers(0, 60000, size=(4, 3, 2, 3))
mif('four.mif', d4, ['+1', '+2', '+3', '+0'], dtype='UInt16LE', vox=(1.5, 2.0, 2.5, float('nan')))
expect('four.mif', d4); convert('four.mif')
mif('four.mif.gz', d4, ['-3', '+0', '-2', '+1'], dtype='UInt16LE', gz=True, vox=(1.5, 2.0, 2.5, 1.0))
expect('four.mif.gz', d4); convert('four.mif.gz')
mif('notransform.mif', d3, ['+0', '+1', '+2'], transform=None, extra='# a comment\ncomments: hello\n')
expect('notransform.mif', d3, transform=None); convert('notransform.mif')
# Lies.
small = rng.integers(0, 9, size=(3, 2, 2)).astype(np.float32)
mif('short.mif', small, ['+0', '+1', '+2'], cut=3)
mif('short.mif.gz', small, ['+0', '+1', '+2'], cut=5, gz=True)
mif('huge.mif', small, ['+0', '+1', '+2'], dims=(100000, 100000, 100000))
mif('twice.mif', small, ['+0', '+0', '+1'])
mif('range.mif', small, ['+0', '+1', '+3'])
mif('word.mif', small, ['+0', '+1', '+2'], extra='layout: +0,x,+2\n')
mif('bit.mif', small, ['+0', '+1', '+2'], dtype='Float32LE', extra='datatype: Bit\n')
mif('complex.mif', small, ['+0', '+1', '+2'], dtype='Float32LE', extra='datatype: CFloat32LE\n')
mif('fifth.mif', small.reshape(3, 2, 2, 1, 1), ['+0', '+1', '+2', '+3', '+4'],
    dims=(3, 2, 2, 1, 2))
)PY";

class MrtrixFiles : public test::NibabelFiles<&kScript> {
 protected:
  // Every frame of `name` equals what the writer stored; mrconvert's NIfTI (when there is one)
  // holds the same value at the same world position for every voxel.
  static void expect_reads(const std::string& name, VoxelType type) {
    const NibabelImage want = read_reference(file(name));
    const VolumeHeader h = read_mrtrix_header(file(name));
    ASSERT_EQ(h.frames, want.frames) << name;
    EXPECT_EQ(h.type, type) << name;
    const bool converted = fs::exists(file(name + ".nii.ref"));
    EXPECT_TRUE(converted || !have_mrconvert()) << name << ": mrconvert wrote nothing";
    const NibabelImage mr = converted ? read_reference(file(name + ".nii")) : NibabelImage{};
    for (int f = 0; f < want.frames; ++f) {
      const VolumeData v = read_mrtrix(file(name), f);
      EXPECT_EQ(v.type(), type) << name;
      expect_equals_reference(v, want, f, name);
      if (converted) expect_same_in_world(v, mr, f, name);
    }
  }

  static void expect_same_in_world(const VolumeData& v, const NibabelImage& r, int frame,
                                   const std::string& name) {
    ASSERT_EQ(r.frames > frame, true) << name;
    const glm::dmat4 to_theirs = glm::inverse(r.lps) * v.index_to_world;
    int wrong = 0;
    for (int k = 0; k < v.dims.z; ++k)
      for (int j = 0; j < v.dims.y; ++j)
        for (int i = 0; i < v.dims.x; ++i) {
          const glm::dvec4 q = to_theirs * glm::dvec4(i, j, k, 1.0);
          const glm::ivec3 n(std::lround(q.x), std::lround(q.y), std::lround(q.z));
          const bool on_grid = std::abs(q.x - n.x) < 1e-3 && std::abs(q.y - n.y) < 1e-3 &&
                               std::abs(q.z - n.z) < 1e-3 &&
                               glm::all(glm::greaterThanEqual(n, glm::ivec3(0))) &&
                               glm::all(glm::lessThan(n, r.dims));
          const double want = on_grid ? r.at(frame, n.x, n.y, n.z) : NAN;
          if (!(std::abs(v.value_at(i, j, k) - want) <= 1e-5 * std::max(1.0, std::abs(want))) &&
              wrong++ < 5)
            ADD_FAILURE() << name << " frame " << frame << ": voxel (" << i << "," << j << "," << k
                          << ") is " << v.value_at(i, j, k) << ", mrconvert's NIfTI holds " << want
                          << " there (its voxel " << q.x << "," << q.y << "," << q.z << ")";
        }
    EXPECT_EQ(wrong, 0) << name << ": voxels differing from mrconvert's";
  }
};

TEST_F(MrtrixFiles, EveryLayoutSignAndPermutationReadsTheImageAxes) {
  for (const char* name : {"p012.mif", "m0.mif", "doc.mif", "p120.mif", "m210.mif"})
    expect_reads(name, VoxelType::f32);
}

TEST_F(MrtrixFiles, ByteOrdersTypesAndScaling) {
  expect_reads("be.mif", VoxelType::f32);
  expect_reads("f64.mif", VoxelType::f32);
  expect_reads("scaled.mif", VoxelType::f32);
  expect_reads("i8.mif", VoxelType::i16);
}

TEST_F(MrtrixFiles, AHeaderWithItsDataInAnotherFile) {
  expect_reads("sep.mih", VoxelType::u8);
}

TEST_F(MrtrixFiles, FourDimensionalVolumeContiguousAndGzipped) {
  expect_reads("four.mif", VoxelType::u16);
  expect_reads("four.mif.gz", VoxelType::u16);
}

TEST_F(MrtrixFiles, WithoutATransformTheGridIsCentredAsMrtrixDoes) {
  expect_reads("notransform.mif", VoxelType::f32);
}

TEST_F(MrtrixFiles, ARegionIsTheCropOfTheWhole) {
  for (const char* name : {"doc.mif", "four.mif", "four.mif.gz", "m210.mif"}) {
    const VoxelBox box{{1, 1, 0}, {3, 2, 2}};
    const VolumeData whole = read_mrtrix(file(name), read_mrtrix_header(file(name)).frames - 1);
    const VolumeData part =
        read_mrtrix_region(file(name), box, read_mrtrix_header(file(name)).frames - 1);
    const VolumeData want = crop(whole, box, name);
    ASSERT_EQ(part.dims, want.dims) << name;
    EXPECT_EQ(part.index_to_world, want.index_to_world) << name;
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 1; ++j)
        for (int i = 0; i < 2; ++i)
          EXPECT_EQ(part.value_at(i, j, k), want.value_at(i, j, k)) << name;
  }
}

TEST_F(MrtrixFiles, LyingHeadersAreRefusedNamingTheKey) {
  expect_error([] { read_mrtrix(file("short.mif")); },
               {"short.mif", "expected 48 bytes", "truncated"});
  expect_error([] { read_mrtrix(file("short.mif.gz")); }, {"short.mif.gz", "truncated"});
  expect_error([] { read_mrtrix(file("huge.mif")); }, {"'dim'", "more than"});
  expect_error([] { read_mrtrix(file("twice.mif")); }, {"'layout'", "rank 0 twice"});
  expect_error([] { read_mrtrix(file("range.mif")); }, {"'layout'", "'+3'"});
  expect_error([] { read_mrtrix(file("word.mif")); }, {"'layout'", "'x'"});
  expect_error([] { read_mrtrix(file("bit.mif")); }, {"'datatype'", "Bit", "not supported"});
  expect_error([] { read_mrtrix(file("complex.mif")); }, {"'datatype'", "complex"});
  expect_error([] { read_mrtrix(file("fifth.mif")); }, {"'dim'", "axis 4"});
  expect_error([] { read_mrtrix(file("four.mif"), 3); }, {"frame 3", "3 frames"});
}

TEST(MrtrixHeader, HandWrittenLies) {
  test::TempDir dir;
  const std::string head =
      "mrtrix image\ndim: 2,1,1\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: UInt8\n";
  auto mif = [&](const std::string& text) { return dir.write("x.mif", text); };
  EXPECT_EQ(read_mrtrix(mif(head + "file: . 100\nEND\n" +
                            std::string(100 - head.size() - 16, '\0') + "\x03\x05"))
                .value_at(1, 0, 0),
            5.0);
  expect_error([&] { read_mrtrix(mif(head + "file: . 10\nEND\n\x03\x05")); },
               {"'file'", "inside the header"});
  expect_error([&] { read_mrtrix(mif(head + "file: . 90\n")); }, {"no END"});
  expect_error([&] { read_mrtrix(mif(head + "END\n")); }, {"missing key 'file'"});
  expect_error([&] { read_mrtrix(mif(head + "file: a.dat\nfile: b.dat\nEND\n")); },
               {"'file'", "second data file"});
  expect_error([&] { read_mrtrix(mif(head + "file: ../../etc/passwd\nEND\n")); }, {"file"});
  expect_error([&] { read_mrtrix(mif("mrtrix imagf\n")); }, {"not an MRtrix image"});
  expect_error([&] { read_mrtrix(mif(head + "transform: 1,0,0,0\nfile: . 200\nEND\n")); },
               {"'transform'", "3 rows"});
  expect_error([&] { read_mrtrix(mif(head + "scaling: 1\nfile: . 200\nEND\n")); }, {"'scaling'"});
  EXPECT_TRUE(detail::is_mrtrix_header(head));
  EXPECT_FALSE(detail::is_mrtrix_header("mrtrix tracks\n"));
}

// The shared template against mrconvert's NIfTI of it, voxel by voxel in world space, and
// against the transform and vox of its header read here by Python.
TEST(MrtrixRealData, TheSharedTemplateEqualsMrconvert) {
  SKIP_WITHOUT_SHARED_DATA("neuro/volumes/template.mif.gz");
  if (!test::have_nibabel()) GTEST_SKIP() << "/usr/bin/python3 with nibabel is not available";
  if (!have_mrconvert()) GTEST_SKIP() << "mrconvert (Debian's mrtrix3) is not installed";
  test::TempDir dir;
  const fs::path real = test::shared_data("neuro/volumes/template.mif.gz");
  std::ostringstream script;
  script << "import subprocess\nsubprocess.run(['mrconvert', '-quiet', '" << real.string()
         << "', 't.nii'], check=True)\nref('t.nii')\n";
  ASSERT_TRUE(test::run_nibabel(dir, script.str()));
  const NibabelImage r = read_reference(dir / "t.nii");
  const VolumeData v = read_mrtrix(real);
  EXPECT_EQ(v.dims, glm::ivec3(96, 96, 60));
  const glm::dmat4 to_theirs = glm::inverse(r.lps) * v.index_to_world;
  int wrong = 0;
  for (int k = 0; k < v.dims.z; ++k)
    for (int j = 0; j < v.dims.y; ++j)
      for (int i = 0; i < v.dims.x; ++i) {
        const glm::dvec4 q = to_theirs * glm::dvec4(i, j, k, 1.0);
        const glm::ivec3 n(std::lround(q.x), std::lround(q.y), std::lround(q.z));
        ASSERT_LT(glm::length(glm::dvec3(q) - glm::dvec3(n)), 1e-3);
        ASSERT_TRUE(glm::all(glm::greaterThanEqual(n, glm::ivec3(0))) &&
                    glm::all(glm::lessThan(n, r.dims)));
        const double want = r.at(0, n.x, n.y, n.z);
        if (v.value_at(i, j, k) != want && wrong++ < 5)
          ADD_FAILURE() << "voxel (" << i << "," << j << "," << k << ") is " << v.value_at(i, j, k)
                        << ", mrconvert's NIfTI holds " << want;
      }
  EXPECT_EQ(wrong, 0);
}

}  // namespace
}  // namespace imx
