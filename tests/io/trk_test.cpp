// TrackVis .trk reader (src/io/streamlines/trk.hpp) against nibabel.streamlines.load: the shared
// data's files, files nibabel writes in every voxel order with non-unit voxel sizes, scalars and
// properties, their big-endian and version 1 variants, and malformed files.
#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "io/streamlines/trk.hpp"
#include "nibabel_reference.hpp"
#include "shared_data.hpp"
#include "streamlines_reference.hpp"

namespace imx::test {
namespace {

// Streamlines in RAS mm with two named scalars (one of 3 values) and two properties (one of 2),
// saved by nibabel with each header; helpers that rewrite a saved file.
const std::string kTrkScript = std::string(kStreamlinesPrelude) + R"PY(
rng = np.random.default_rng(7)

def save_trk(name, order='RAS', aff=np.eye(4), vs=(1, 1, 1), dims=(10, 10, 10), values=True,
             streamlines=None):
    sl = streamlines or [np.float32([10, -20, 30]) + np.cumsum(rng.normal(size=(k, 3)), axis=0)
                         .astype(np.float32) for k in rng.integers(2, 30, 6)]
    dpp, dps = {}, {}
    if values:
        dpp = {'fa': [rng.random((len(s), 1)).astype(np.float32) for s in sl],
               'rgb': [rng.random((len(s), 3)).astype(np.float32) for s in sl]}
        dps = {'weight': rng.random((len(sl), 1)).astype(np.float32),
               'pair': rng.random((len(sl), 2)).astype(np.float32)}
    tg = Tractogram(sl, data_per_point=dpp, data_per_streamline=dps, affine_to_rasmm=np.eye(4))
    hdr = {'voxel_to_rasmm': np.asarray(aff, np.float32), 'voxel_sizes': np.float32(vs),
           'dimensions': np.int16(dims), 'voxel_order': order}
    nib.streamlines.TrkFile(tg, header=hdr).save(name)

def patch(name, out, offset, fmt, *value):
    b = bytearray(open(name, 'rb').read())
    struct.pack_into(fmt, b, offset, *value)
    open(out, 'wb').write(bytes(b))

def to_big_endian(name, out):
    b = open(name, 'rb').read()
    hdr = np.frombuffer(b[:1000], header_2_dtype).astype(header_2_dtype.newbyteorder('>'))
    open(out, 'wb').write(hdr.tobytes() + np.frombuffer(b[1000:], '<u4').byteswap().tobytes())

vs = (1.25, 1.5, 2.0)
dims = (91, 109, 60)
c, s = np.cos(0.2), np.sin(0.2)
rot = np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
affines = {
    'diag': [[1.25, 0, 0, -90], [0, 1.5, 0, -120], [0, 0, 2, -60], [0, 0, 0, 1]],
    # voxel axes permuted and flipped against RAS, then turned 11 degrees about z
    'oblique': rot @ np.array([[0, -1.5, 0, 100], [1.25, 0, 0, -80], [0, 0, -2, 70], [0, 0, 0, 1]]),
}
names = []
for order in ['LPS', 'RAS', 'LAS', 'RPI', 'PLS', 'SAR', 'las']:
    for key, aff in affines.items():
        name = f'order_{order}_{key}.trk'
        save_trk(name, order, aff, vs, dims)
        ref(name)
        names.append(name)
open('orders.txt', 'w').write('\n'.join(names))

save_trk('plain.trk', 'LAS', affines['oblique'], vs, dims)
ref('plain.trk')
to_big_endian('plain.trk', 'big.trk')
ref('big.trk')
patch('plain.trk', 'v1.trk', 992, '<i', 1)
ref('v1.trk')
patch('plain.trk', 'no_affine.trk', 440, '<16f', *([0.0] * 16))
ref('no_affine.trk')
patch('plain.trk', 'no_order.trk', 948, '<4s', b'')
ref('no_order.trk')
patch('plain.trk', 'count0.trk', 988, '<i', 0)
ref('count0.trk')
save_trk('bare.trk', 'LPS', affines['diag'], vs, dims, values=False)
ref('bare.trk')

# streamlines intermix drops: a NaN coordinate, one point, no point
odd = [np.float32([[1, 2, 3], [4, 5, 6], [7, 8, 9]]), np.float32([[1, np.nan, 3], [4, 5, 6]]),
       np.float32([[5, 5, 5]]), np.zeros((0, 3), np.float32), np.float32([[0, 0, 0], [1, 1, 1]])]
save_trk('odd.trk', 'RAS', affines['diag'], vs, dims, values=False, streamlines=odd)
ref('odd.trk')

# nibabel does not write a streamline of no points: one added after the last (n_count 0)
patch('bare.trk', 'zero_points.trk', 988, '<i', 0)
open('zero_points.trk', 'ab').write(struct.pack('<i', 0))
ref('zero_points.trk')

# malformed
n = nib.streamlines.load('plain.trk').header['nb_streamlines']
size = os.path.getsize('plain.trk')
open('truncated.trk', 'wb').write(open('plain.trk', 'rb').read()[:size - 7])
patch('plain.trk', 'lying_count.trk', 988, '<i', n + 3)
patch('plain.trk', 'fewer_count.trk', 988, '<i', n - 2)
ref('fewer_count.trk')
patch('plain.trk', 'huge_count.trk', 988, '<i', 2**31 - 1)
patch('plain.trk', 'negative_count.trk', 988, '<i', -4)
patch('plain.trk', 'bad_hdr_size.trk', 996, '<i', 999)
patch('plain.trk', 'version4.trk', 992, '<i', 4)
patch('plain.trk', 'singular.trk', 440, '<16f', 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1)
patch('plain.trk', 'nan_affine.trk', 440, '<f', np.nan)
patch('plain.trk', 'bad_order.trk', 948, '<4s', b'XYZ')
patch('plain.trk', 'twice_order.trk', 948, '<4s', b'LLS')
patch('plain.trk', 'zero_voxel.trk', 16, '<f', 0.0)
patch('plain.trk', 'negative_points.trk', 1000, '<i', -5)
patch('plain.trk', 'overrun_points.trk', 1000, '<i', 10**6)
patch('plain.trk', 'negative_scalars.trk', 36, '<h', -2)
patch('plain.trk', 'not_track.trk', 0, '<5s', b'TRACX')
patch('plain.trk', 'bad_name.trk', 38, '<20s', b'fa\x00\x003')
patch('plain.trk', 'bad_count_name.trk', 38, '<20s', b'fa\x00x')
open('short.trk', 'wb').write(open('plain.trk', 'rb').read()[:600])
# n_count 0 with 2 stray bytes after the last streamline
b = open('count0.trk', 'rb').read()
open('stray.trk', 'wb').write(b + b'\x01\x02')
# names: one of several values given as "name\0N", and more scalars than names
patch('plain.trk', 'packed.trk', 38, '<20s20s', b'a\x002', b'')
ref('packed.trk')
)PY";
const char* const kTrkScriptText = kTrkScript.c_str();
using TrkFiles = NibabelFiles<&kTrkScriptText>;

Streamlines read(const std::filesystem::path& file, std::vector<std::string>& notes) {
  return detail::read_trk(file, notes);
}

void expect_matches_nibabel(const std::filesystem::path& file,
                            std::vector<std::string>* notes_out = nullptr) {
  std::vector<std::string> notes;
  const Streamlines s = read(file, notes);
  expect_streamlines_match(s, read_streamlines_reference(file.string() + ".ref"),
                           file.filename().string());
  if (notes_out != nullptr) *notes_out = notes;
}

TEST(Trk, SharedFilesMatchNibabel) {
  SKIP_WITHOUT_SHARED_DATA("neuro/tracts");
  if (!have_nibabel()) GTEST_SKIP() << "/usr/bin/python3 with nibabel is not available";
  TempDir dir;
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(shared_data("neuro/tracts")))
    if (e.path().extension() == ".trk") files.push_back(e.path());
  ASSERT_FALSE(files.empty());
  std::string script;
  for (const auto& f : files)
    script += "ref('" + f.string() + "', '" + (dir / f.filename()).string() + ".ref')\n";
  ASSERT_TRUE(run_nibabel(dir, std::string(kStreamlinesPrelude) + script));
  for (const auto& f : files) {
    std::vector<std::string> notes;
    const Streamlines s = read(f, notes);
    EXPECT_GT(s.count(), 0u) << f;
    expect_streamlines_match(s, read_streamlines_reference((dir / f.filename()).string() + ".ref"),
                             f.filename().string());
  }
}

TEST(Trk, ColbyScalarNamesAreTrimmed) {
  SKIP_WITHOUT_SHARED_DATA("neuro/tracts/colby.trk");
  std::vector<std::string> notes;
  const Streamlines s = read(shared_data("neuro/tracts/colby.trk"), notes);
  ASSERT_EQ(s.point_values.size(), 3u);
  EXPECT_EQ(s.point_values[0].name, "effect");
  EXPECT_EQ(s.point_values[2].name, "pval_corr");
  EXPECT_TRUE(has_note(notes, "vox_to_ras is not recorded"));
}

TEST_F(TrkFiles, EveryVoxelOrderMatchesNibabel) {
  const std::string list = read_bytes(file("orders.txt"));
  size_t start = 0, files = 0;
  while (start < list.size()) {
    size_t end = list.find('\n', start);
    if (end == std::string::npos) end = list.size();
    expect_matches_nibabel(file(list.substr(start, end - start)));
    ++files;
    start = end + 1;
  }
  EXPECT_EQ(files, 14u);
}

TEST_F(TrkFiles, ScalarsAndPropertiesAreNamedAsNibabelNamesThem) {
  std::vector<std::string> notes;
  const Streamlines s = read(file("plain.trk"), notes);
  std::vector<std::string> points, streamlines;
  for (const StreamlineValues& v : s.point_values) points.push_back(v.name);
  for (const StreamlineValues& v : s.streamline_values) streamlines.push_back(v.name);
  EXPECT_EQ(points, (std::vector<std::string>{"fa", "rgb[0]", "rgb[1]", "rgb[2]"}));
  EXPECT_EQ(streamlines, (std::vector<std::string>{"pair[0]", "pair[1]", "weight"}));
  EXPECT_TRUE(notes.empty()) << notes.front();
  expect_matches_nibabel(file("plain.trk"));
  expect_matches_nibabel(file("bare.trk"));
}

TEST_F(TrkFiles, PackedNameAndUnnamedScalars) {
  // "a\0" "2" names 2 values; the other 2 of n_scalars 4 are nibabel's "scalars".
  std::vector<std::string> notes;
  const Streamlines s = read(file("packed.trk"), notes);
  ASSERT_EQ(s.point_values.size(), 4u);
  EXPECT_EQ(s.point_values[0].name, "a[0]");
  EXPECT_EQ(s.point_values[3].name, "scalars[1]");
  expect_matches_nibabel(file("packed.trk"));
}

TEST_F(TrkFiles, BigEndianMatchesNibabel) {
  expect_matches_nibabel(file("big.trk"));
}

TEST_F(TrkFiles, VersionOneAndUnrecordedAffineAreTheIdentity) {
  for (const char* name : {"v1.trk", "no_affine.trk"}) {
    std::vector<std::string> notes;
    expect_matches_nibabel(file(name), &notes);
    EXPECT_TRUE(has_note(notes, "vox_to_ras is not recorded")) << name;
  }
}

TEST_F(TrkFiles, EmptyVoxelOrderIsLps) {
  std::vector<std::string> notes;
  expect_matches_nibabel(file("no_order.trk"), &notes);
  EXPECT_TRUE(has_note(notes, "taken as LPS"));
}

TEST_F(TrkFiles, CountZeroReadsToTheEnd) {
  std::vector<std::string> notes;
  expect_matches_nibabel(file("count0.trk"), &notes);
  EXPECT_TRUE(notes.empty());
}

TEST_F(TrkFiles, BytesAfterNCountStreamlinesAreNoted) {
  std::vector<std::string> notes;
  expect_matches_nibabel(file("fewer_count.trk"), &notes);
  EXPECT_TRUE(has_note(notes, "bytes after the 4 streamlines of n_count are ignored"));
}

TEST_F(TrkFiles, NanPointsAndShortStreamlinesAreDroppedWithANote) {
  std::vector<std::string> notes;
  expect_matches_nibabel(file("odd.trk"), &notes);
  EXPECT_TRUE(has_note(notes,
                       "1 streamline of fewer than 2 points dropped (the first: "
                       "streamline 2"));
  EXPECT_TRUE(has_note(notes,
                       "1 streamline with NaN or infinite coordinates dropped (the "
                       "first: streamline 1"));
  expect_matches_nibabel(file("zero_points.trk"), &notes);
  EXPECT_TRUE(has_note(notes,
                       "1 streamline of fewer than 2 points dropped (the first: "
                       "streamline 6"));
}

TEST_F(TrkFiles, MalformedFilesGiveOneClearError) {
  const std::vector<std::pair<const char*, std::vector<std::string>>> cases = {
      {"truncated.trk", {"truncated.trk", "claims", "points"}},
      {"lying_count.trk", {"n_count says", "the file ends after"}},
      {"huge_count.trk", {"n_count says 2147483647", "can hold"}},
      {"negative_count.trk", {"n_count is -4"}},
      {"bad_hdr_size.trk", {"hdr_size is 999"}},
      {"version4.trk", {"version 4"}},
      {"singular.trk", {"vox_to_ras is singular"}},
      {"nan_affine.trk", {"vox_to_ras holds nan"}},
      {"bad_order.trk", {"voxel_order 'XYZ'"}},
      {"twice_order.trk", {"voxel_order 'LLS'"}},
      {"zero_voxel.trk", {"voxel_size y is 0"}},
      {"negative_points.trk", {"streamline 0 has a point count of -5"}},
      {"overrun_points.trk", {"streamline 0 claims 1000000 points"}},
      {"negative_scalars.trk", {"n_scalars is -2"}},
      {"not_track.trk", {"not a TrackVis file"}},
      {"bad_name.trk", {"scalar_name 0", "should be NUL"}},
      {"bad_count_name.trk", {"scalar_name 0", "not a count of values"}},
      {"short.trk", {"shorter than the 1000-byte"}},
      {"stray.trk", {"ends inside the point count", "2 bytes left"}},
  };
  for (const auto& [name, fragments] : cases) {
    std::vector<std::string> notes;
    const std::string message = error_of([&, n = name] { read(file(n), notes); });
    EXPECT_CONTAINS(message, name);
    for (const std::string& f : fragments) EXPECT_CONTAINS(message, f);
  }
}

}  // namespace
}  // namespace imx::test
