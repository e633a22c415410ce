// MRtrix .tck reader and .tsf scalars (src/io/streamlines/tck.hpp) against nibabel.streamlines.load
// (and, for what nibabel does not read, float64 and .tsf, a numpy parse that splits the values at
// their NaN records): the shared data's files, files nibabel writes, big-endian and float64 files
// written byte by byte, and malformed files.
#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "io/streamlines/tck.hpp"
#include "nibabel_reference.hpp"
#include "shared_data.hpp"
#include "streamlines_reference.hpp"

namespace imx::test {
namespace {

const std::string kTckScript = std::string(kStreamlinesPrelude) + R"PY(
rng = np.random.default_rng(11)
sl = [np.float32([-10, 20, 5]) + np.cumsum(rng.normal(size=(k, 3)), axis=0).astype(np.float32)
      for k in rng.integers(2, 40, 9)]
nib.streamlines.save(Tractogram(sl, affine_to_rasmm=np.eye(4)), 'nibabel.tck')
ref('nibabel.tck')

# nibabel reads float32 big-endian but writes only little-endian; float64 it does not read.
for dtype, name in [('>f4', 'big32'), ('<f8', 'little64'), ('>f8', 'big64')]:
    write_mrtrix(name + '.tck', 'mrtrix tracks', sl, dtype, 3, {'count': len(sl)})
    runs = mrtrix_runs(name + '.tck', 3)
    write_ref(name + '.tck.ref', runs, {}, {})
ref('big32.tck', 'big32.tck.nibabel.ref')

# scalars for nibabel.tck: one value per point, and one that does not pair
fa = [rng.random(len(s)) for s in sl]
write_mrtrix('fa.tsf', 'mrtrix track scalars', [f.reshape(-1, 1) for f in fa], '<f4', 1,
             {'count': len(sl)})
runs = mrtrix_runs('fa.tsf', 1)
write_ref('fa.tsf.ref', [np.zeros((len(r), 3)) for r in runs], {'fa': np.concatenate(runs)}, {})
write_mrtrix('fa64be.tsf', 'mrtrix track scalars', [f.reshape(-1, 1) for f in fa], '>f8', 1)
bad = [f.reshape(-1, 1) for f in fa]
bad[3] = bad[3][:-1]
write_mrtrix('short_run.tsf', 'mrtrix track scalars', bad, '<f4', 1)
write_mrtrix('fewer.tsf', 'mrtrix track scalars', bad[:5], '<f4', 1)

# streamlines intermix drops (nibabel keeps them): a NaN coordinate, one point
odd = [sl[0], np.float32([[1, np.nan, 3], [4, 5, 6]]), np.float32([[7, 7, 7]]), sl[1]]
write_mrtrix('odd.tck', 'mrtrix tracks', odd, '<f4', 3, {'count': 4})
ref('odd.tck')
write_mrtrix('odd.tsf', 'mrtrix track scalars', [np.arange(len(s)).reshape(-1, 1) for s in odd],
             '<f4', 1)

short = [sl[0], np.float32([[7, 7, 7]]), sl[1]]
write_mrtrix('short.tck', 'mrtrix tracks', short, '<f4', 3)
write_mrtrix('short.tsf', 'mrtrix track scalars', [np.arange(len(s)).reshape(-1, 1) for s in short],
             '<f4', 1)

write_mrtrix('lying_count.tck', 'mrtrix tracks', sl, '<f4', 3, {'count': 3})
ref('lying_count.tck')
write_mrtrix('no_end.tck', 'mrtrix tracks', sl, '<f4', 3, end=False)
write_ref('no_end.tck.ref', mrtrix_runs('no_end.tck', 3), {}, {})
b = open('nibabel.tck', 'rb').read()
open('after_end.tck', 'wb').write(b + b'\0' * 12)
open('truncated.tck', 'wb').write(b[:len(b) - 12 - 12 * 3 - 5])
# an empty streamline: two delimiters in a row
write_mrtrix('empty_run.tck', 'mrtrix tracks', [sl[0], np.zeros((0, 3)), sl[1]], '<f4', 3)
ref('empty_run.tck')

# malformed
open('not_tracks.tck', 'wb').write(b'mrtrix image\nEND\n')
open('no_end_line.tck', 'wb').write(b'mrtrix tracks\ndatatype: Float32LE\nfile: . 40\n')
open('int_type.tck', 'wb').write(b.replace(b'Float32LE', b'Int32LE\0\0'))
open('far_offset.tck', 'wb').write(b'mrtrix tracks\ndatatype: Float32LE\nfile: . 99999\nEND\n')
open('inside_offset.tck', 'wb').write(b'mrtrix tracks\ndatatype: Float32LE\nfile: . 3\nEND\n')
open('other_file.tck', 'wb').write(b'mrtrix tracks\ndatatype: Float32LE\nfile: x.dat 0\nEND\n')
open('orphan_line.tck', 'wb').write(b'mrtrix tracks\norphan\nEND\n')
)PY";
const char* const kTckScriptText = kTckScript.c_str();
using TckFiles = NibabelFiles<&kTckScriptText>;

Streamlines expect_matches(const std::filesystem::path& file, const std::string& ref_suffix,
                           std::vector<std::string>& notes) {
  Streamlines s = detail::read_tck(file, notes);
  expect_streamlines_match(s, read_streamlines_reference(file.string() + ref_suffix),
                           file.filename().string());
  return s;
}

TEST(Tck, SharedFilesMatchNibabel) {
  SKIP_WITHOUT_SHARED_DATA("neuro/tracts");
  if (!have_nibabel()) GTEST_SKIP() << "/usr/bin/python3 with nibabel is not available";
  TempDir dir;
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(shared_data("neuro/tracts")))
    if (e.path().extension() == ".tck") files.push_back(e.path());
  ASSERT_FALSE(files.empty());
  std::string script;
  for (const auto& f : files)
    script += "ref('" + f.string() + "', '" + (dir / f.filename()).string() + ".ref')\n";
  ASSERT_TRUE(run_nibabel(dir, std::string(kStreamlinesPrelude) + script));
  for (const auto& f : files) {
    std::vector<std::string> notes;
    const Streamlines s = detail::read_tck(f, notes);
    EXPECT_GT(s.count(), 0u) << f;
    EXPECT_TRUE(notes.empty()) << notes.front();
    expect_streamlines_match(s, read_streamlines_reference((dir / f.filename()).string() + ".ref"),
                             f.filename().string());
  }
}

// tcksample's TSF of the shared tract: its values against the numpy parse, paired point for point.
TEST(Tck, SharedTsfPairsWithItsTracks) {
  SKIP_WITHOUT_SHARED_DATA("neuro/tracts/tract.SLF1_R.tck", "neuro/tracts/mni152.SLF1_R.tsf");
  if (!have_nibabel()) GTEST_SKIP() << "/usr/bin/python3 with nibabel is not available";
  const std::filesystem::path tck = shared_data("neuro/tracts/tract.SLF1_R.tck"),
                              tsf = shared_data("neuro/tracts/mni152.SLF1_R.tsf");
  TempDir dir;
  ASSERT_TRUE(
      run_nibabel(dir, std::string(kStreamlinesPrelude) + "runs = mrtrix_runs('" + tsf.string() +
                           "', 1)\nwrite_ref('tsf.ref', [np.zeros((len(r), 3)) for r in runs], "
                           "{'v': np.concatenate(runs)}, {})\n"));
  const StreamlinesReference r = read_streamlines_reference(dir / "tsf.ref");
  std::vector<std::string> notes;
  Streamlines s = detail::read_tck(tck, notes);
  detail::read_tsf(tsf, s, notes, tck);
  EXPECT_TRUE(notes.empty()) << notes.front();
  ASSERT_EQ(s.point_values.size(), 1u);
  EXPECT_EQ(s.point_values[0].name, "mni152.SLF1_R");
  ASSERT_EQ(r.lengths.size(), s.count());
  ASSERT_EQ(s.point_values[0].values.size(), r.point_values[0].second.size());
  for (size_t i = 0; i < s.count(); ++i) EXPECT_EQ(s.length(i), size_t(r.lengths[i]));
  for (size_t i = 0; i < s.points.size(); ++i)
    EXPECT_EQ(s.point_values[0].values[i], float(r.point_values[0].second[i])) << i;
}

TEST_F(TckFiles, NibabelFileMatches) {
  std::vector<std::string> notes;
  expect_matches(file("nibabel.tck"), ".ref", notes);
  EXPECT_TRUE(notes.empty()) << notes.front();
}

TEST_F(TckFiles, BigEndianAndFloat64Match) {
  for (const char* name : {"big32.tck", "little64.tck", "big64.tck"}) {
    std::vector<std::string> notes;
    expect_matches(file(name), ".ref", notes);
    EXPECT_TRUE(notes.empty()) << name << ": " << notes.front();
  }
  // nibabel itself reads the big-endian float32 file.
  std::vector<std::string> notes;
  expect_matches(file("big32.tck"), ".nibabel.ref", notes);
  // and the float64 files hold the same streamlines as nibabel's float32 file.
  expect_matches(file("big64.tck"), ".ref", notes);
  expect_streamlines_match(detail::read_tck(file("big64.tck"), notes),
                           read_streamlines_reference(file("nibabel.tck").string() + ".ref"),
                           "big64.tck against nibabel.tck");
}

TEST_F(TckFiles, TsfValuesPairWithTheTracks) {
  std::vector<std::string> notes;
  Streamlines s = detail::read_tck(file("nibabel.tck"), notes);
  detail::read_tsf(file("fa.tsf"), s, notes, file("nibabel.tck"));
  detail::read_tsf(file("fa64be.tsf"), s, notes, file("nibabel.tck"));
  EXPECT_TRUE(notes.empty()) << notes.front();
  const StreamlinesReference r = read_streamlines_reference(file("fa.tsf").string() + ".ref");
  ASSERT_EQ(s.point_values.size(), 2u);
  EXPECT_EQ(s.point_values[0].name, "fa");
  EXPECT_EQ(s.point_values[1].name, "fa64be");
  ASSERT_EQ(r.lengths.size(), s.count());
  ASSERT_EQ(s.point_values[0].values.size(), r.points.size());
  for (size_t i = 0; i < r.points.size(); ++i) {
    EXPECT_EQ(s.point_values[0].values[i], float(r.point_values[0].second[i])) << i;
    EXPECT_EQ(s.point_values[1].values[i], float(r.point_values[0].second[i])) << i;
  }
}

TEST_F(TckFiles, TsfThatDoesNotPairIsOneErrorNamingBothFiles) {
  for (const char* name : {"short_run.tsf", "fewer.tsf"}) {
    std::vector<std::string> notes;
    Streamlines s = detail::read_tck(file("nibabel.tck"), notes);
    const std::string message =
        error_of([&] { detail::read_tsf(file(name), s, notes, file("nibabel.tck")); });
    EXPECT_CONTAINS(message, name);
    EXPECT_CONTAINS(message, "nibabel.tck");
    EXPECT_TRUE(s.point_values.empty());
  }
}

TEST_F(TckFiles, DroppedStreamlinesAreNotedAndTheirTsfSkipped) {
  std::vector<std::string> notes;
  Streamlines s = expect_matches(file("odd.tck"), ".ref", notes);
  EXPECT_TRUE(has_note(notes,
                       "1 streamline of fewer than 2 points dropped (the first: "
                       "streamline 2"));
  EXPECT_TRUE(has_note(notes,
                       "1 streamline with NaN or infinite coordinates dropped (the "
                       "first: streamline 1"));
  // The 1-point streamline's value is skipped; the NaN streamline's 2 cannot be paired.
  const std::string message =
      error_of([&] { detail::read_tsf(file("odd.tsf"), s, notes, file("odd.tck")); });
  EXPECT_CONTAINS(message, "odd.tsf");
  EXPECT_CONTAINS(message, "odd.tck");
}

TEST_F(TckFiles, TsfOfADroppedOnePointStreamlineIsSkipped) {
  std::vector<std::string> notes;
  Streamlines s = detail::read_tck(file("short.tck"), notes);
  ASSERT_EQ(s.count(), 2u);
  detail::read_tsf(file("short.tsf"), s, notes, file("short.tck"));
  EXPECT_TRUE(has_note(notes, "1 streamlines of fewer than 2 values skipped"));
  ASSERT_EQ(s.point_values.size(), 1u);
  ASSERT_EQ(s.point_values[0].values.size(), s.points.size());
  for (size_t i = 0; i < s.count(); ++i)
    for (size_t k = 0; k < s.length(i); ++k)
      EXPECT_EQ(s.point_values[0].values[s.offsets[i] + k], float(k));
}

TEST_F(TckFiles, CountThatLiesIsNoted) {
  std::vector<std::string> notes;
  expect_matches(file("lying_count.tck"), ".ref", notes);
  EXPECT_TRUE(has_note(notes, "count says 3 streamlines, the file holds 9"));
}

TEST_F(TckFiles, MissingEndMarkerReadsToTheEnd) {
  std::vector<std::string> notes;
  expect_matches(file("no_end.tck"), ".ref", notes);
  EXPECT_TRUE(has_note(notes, "no end marker"));
}

TEST_F(TckFiles, BytesAfterTheEndMarkerAreNoted) {
  std::vector<std::string> notes;
  Streamlines s = detail::read_tck(file("after_end.tck"), notes);
  expect_streamlines_match(s, read_streamlines_reference(file("nibabel.tck").string() + ".ref"),
                           "after_end.tck");
  EXPECT_TRUE(has_note(notes, "12 bytes after the end marker"));
}

TEST_F(TckFiles, TruncatedFileDropsTheStreamlineCutShort) {
  std::vector<std::string> notes;
  const Streamlines s = detail::read_tck(file("truncated.tck"), notes);
  const StreamlinesReference r = read_streamlines_reference(file("nibabel.tck").string() + ".ref");
  EXPECT_EQ(s.count(), r.lengths.size() - 1);
  EXPECT_TRUE(has_note(notes, "not ended by a NaN delimiter"));
  EXPECT_TRUE(has_note(notes, "bytes into a point"));
  EXPECT_TRUE(has_note(notes, "no end marker"));
}

TEST_F(TckFiles, EmptyStreamlineIsSkippedAsNibabelDoes) {
  std::vector<std::string> notes;
  expect_matches(file("empty_run.tck"), ".ref", notes);
  EXPECT_TRUE(has_note(notes, "1 empty streamline"));
}

TEST_F(TckFiles, MalformedHeadersGiveOneClearError) {
  const std::vector<std::pair<const char*, std::vector<std::string>>> cases = {
      {"not_tracks.tck", {"does not start with 'mrtrix tracks'"}},
      {"no_end_line.tck", {"no END line"}},
      {"int_type.tck", {"datatype 'Int32LE"}},
      {"far_offset.tck", {"file offset '99999' is not a byte of the file"}},
      {"inside_offset.tck", {"file offset 3 lies inside the header"}},
      {"other_file.tck", {"file 'x.dat 0' is not '. OFFSET'"}},
      {"orphan_line.tck", {"'orphan' comes before any"}},
  };
  for (const auto& [name, fragments] : cases) {
    std::vector<std::string> notes;
    const std::string message = error_of([&, n = name] { detail::read_tck(file(n), notes); });
    EXPECT_CONTAINS(message, name);
    for (const std::string& f : fragments) EXPECT_CONTAINS(message, f);
  }
}

}  // namespace
}  // namespace imx::test
