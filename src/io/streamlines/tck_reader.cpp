// MRtrix .tck (tck.hpp): one walk over the records counts the streamlines and points, a second
// converts them into the arrays sized by the first.
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streamlines/mapped_file.hpp"
#include "io/streamlines/mrtrix_tracks.hpp"
#include "io/streamlines/streamline_drops.hpp"
#include "io/streamlines/tck.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {

Streamlines read_tck(const std::filesystem::path& file, std::vector<std::string>& notes) {
  const std::string what = file.string();
  const MappedFile map(file);
  const MrtrixTrackFile tck = parse_mrtrix_track_header(map.bytes(), "mrtrix tracks", what, notes);
  Streamlines out;
  StreamlineDrops drops;
  const TrackRuns runs = with_track_value_type(tck.type, [&](auto value, auto big) {
    using T = decltype(value);
    constexpr bool kBig = decltype(big)::value;
    const TrackRuns found = walk_track_runs<T, kBig, 3>(tck.data, [](const char*, uint64_t) {});
    if (found.records > std::numeric_limits<uint32_t>::max())
      throw Error(
          fmt::format("{}: {} points, more than the 2^32 intermix can index", what, found.records));
    check_memory(found.records * sizeof(glm::vec3) + found.runs * 4, what);
    out.points.resize(found.records);
    out.offsets.reserve(found.runs + 1);
    glm::vec3* points = out.points.data();
    size_t kept_points = 0;
    uint64_t index = 0;
    walk_track_runs<T, kBig, 3>(tck.data, [&](const char* p, uint64_t n) {
      bool finite = true;
      for (uint64_t k = 0; k < n; ++k, p += 3 * sizeof(T)) {
        // RAS mm to LPS mm.
        const glm::vec3 q(-static_cast<float>(load_stored<T, kBig>(p)),
                          -static_cast<float>(load_stored<T, kBig>(p + sizeof(T))),
                          static_cast<float>(load_stored<T, kBig>(p + 2 * sizeof(T))));
        finite = finite && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
        points[kept_points + k] = q;
      }
      if (n < 2) {
        drops.too_short(index);
      } else if (!finite) {
        drops.not_finite(index);
      } else {
        kept_points += n;
        out.offsets.push_back(static_cast<uint32_t>(kept_points));
      }
      ++index;
    });
    out.points.resize(kept_points);
    return found;
  });
  note_track_runs(runs, true, what, notes);
  if (const std::string* count = tck.field("count")) {
    const std::optional<uint64_t> said = parse_header_number<uint64_t>(*count);
    if (!said)
      notes.push_back(fmt::format("{}: count '{}' is not a number: the file holds {} streamlines",
                                  what, shown(*count), runs.runs));
    else if (*said != runs.runs)
      notes.push_back(
          fmt::format("{}: count says {} streamlines, the file holds {}: all of them "
                      "are read (as nibabel does)",
                      what, *said, runs.runs));
  }
  drops.report(what, notes);
  return out;
}

}  // namespace imx::detail
