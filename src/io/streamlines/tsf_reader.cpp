// MRtrix track scalar files (tck.hpp's read_tsf): one value per point, laid out as .tck is, matched
// streamline by streamline to the tracks already read.
#include <cstdint>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streamlines/mapped_file.hpp"
#include "io/streamlines/mrtrix_tracks.hpp"
#include "io/streamlines/tck.hpp"

namespace imx::detail {
namespace {

// The TSF's runs that pair with the tracks' streamlines: all of them, or (where the tracks' reader
// dropped streamlines of fewer than 2 points) those of 2 values or more. Throws naming both files
// when neither pairs.
std::vector<size_t> pair_runs(const std::vector<uint32_t>& lengths, const Streamlines& s,
                              const std::string& tsf_name, const std::string& tracks_name) {
  std::string mismatch;
  for (const bool skip_short : {false, true}) {
    std::vector<size_t> runs;
    for (size_t i = 0; i < lengths.size(); ++i)
      if (!skip_short || lengths[i] >= 2) runs.push_back(i);
    if (runs.size() != s.count()) {
      if (mismatch.empty())
        mismatch = fmt::format("{}: {} streamlines of values, {} has {} streamlines", tsf_name,
                               lengths.size(), tracks_name, s.count());
      continue;
    }
    size_t i = 0;
    while (i < runs.size() && lengths[runs[i]] == s.length(i)) ++i;
    if (i == runs.size()) return runs;
    if (mismatch.empty())
      mismatch = fmt::format("{}: streamline {} has {} values, streamline {} of {} has {} points",
                             tsf_name, runs[i], lengths[runs[i]], i, tracks_name, s.length(i));
  }
  throw Error(mismatch);
}

}  // namespace

void read_tsf(const std::filesystem::path& tsf, Streamlines& s, std::vector<std::string>& notes,
              const std::filesystem::path& tracks) {
  const std::string what = tsf.string();
  const MappedFile map(tsf);
  const MrtrixTrackFile file =
      parse_mrtrix_track_header(map.bytes(), "mrtrix track scalars", what, notes);
  std::vector<uint32_t> lengths;
  std::vector<float> values;
  const TrackRuns runs = with_track_value_type(file.type, [&](auto value, auto big) {
    using T = decltype(value);
    constexpr bool kBig = decltype(big)::value;
    const TrackRuns found = walk_track_runs<T, kBig, 1>(file.data, [](const char*, uint64_t) {});
    // Fewer values or streamlines than the tracks' can never pair: said before allocating.
    if (found.records < s.points.size() || found.runs < s.count())
      throw Error(fmt::format("{}: {} streamlines of {} values, {} has {} streamlines of {} points",
                              what, found.runs, found.records, tracks.string(), s.count(),
                              s.points.size()));
    check_memory(found.records * 4 + found.runs * 4, what);
    lengths.reserve(found.runs);
    values.reserve(found.records);
    walk_track_runs<T, kBig, 1>(file.data, [&](const char* p, uint64_t n) {
      lengths.push_back(static_cast<uint32_t>(n));
      for (uint64_t k = 0; k < n; ++k, p += sizeof(T))
        values.push_back(static_cast<float>(load_stored<T, kBig>(p)));
    });
    return found;
  });
  const std::vector<size_t> paired = pair_runs(lengths, s, what, tracks.string());
  note_track_runs(runs, false, what, notes);
  if (paired.size() < lengths.size())
    notes.push_back(
        fmt::format("{}: {} streamlines of fewer than 2 values skipped, as the "
                    "tracks' were",
                    what, lengths.size() - paired.size()));

  StreamlineValues array{tsf.stem().string(), {}};
  array.values.reserve(s.points.size());
  std::vector<uint64_t> starts(lengths.size() + 1, 0);
  for (size_t i = 0; i < lengths.size(); ++i) starts[i + 1] = starts[i] + lengths[i];
  for (size_t run : paired)
    array.values.insert(array.values.end(), values.begin() + static_cast<ptrdiff_t>(starts[run]),
                        values.begin() + static_cast<ptrdiff_t>(starts[run + 1]));
  s.point_values.push_back(std::move(array));
}

}  // namespace imx::detail
