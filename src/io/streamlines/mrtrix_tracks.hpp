// MRtrix's track files: .tck (x y z per point) and .tsf (one value per point). A text header
// ("mrtrix tracks" / "mrtrix track scalars", "key: value" lines, "END"), then from the byte that
// "file: . OFFSET" names, records of `width` values; an all-NaN record ends a streamline and an
// all-infinite one ends the file. Read as nibabel 5.0 reads .tck (streamlines/tck.py), with
// MRtrix's float64 types and its files that end without the marker.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "io/streamlines/stored_values.hpp"

namespace imx::detail {

enum class TrackValueType { float32le, float32be, float64le, float64be };

struct MrtrixTrackFile {
  std::vector<std::pair<std::string, std::string>> fields;  // a repeated key's lines joined by \n
  std::string_view data;  // from the data offset to the end of the file
  TrackValueType type = TrackValueType::float32le;

  const std::string* field(std::string_view key) const {
    for (const auto& [k, v] : fields)
      if (k == key) return &v;
    return nullptr;
  }
};

// Throws imx::Error naming `what`: no `magic` at the start, no END line within 1 MiB, a line
// before any key, a datatype other than Float32LE/BE and Float64LE/BE, a 'file' that is not
// ". OFFSET" inside the file and past the header. A missing datatype (Float32LE) or file (the
// byte after END) is said in `notes`.
MrtrixTrackFile parse_mrtrix_track_header(std::string_view bytes, std::string_view magic,
                                          const std::string& what, std::vector<std::string>& notes);

// What a walk over the records found.
struct TrackRuns {
  uint64_t runs = 0;     // streamlines: non-empty runs ended by a delimiter
  uint64_t records = 0;  // the records in them
  uint64_t empty = 0;    // delimiters with no record before them
  bool end_marker = false;
  uint64_t unterminated = 0;   // records after the last delimiter, not ended by one
  uint64_t bytes_after = 0;    // bytes after the end marker
  uint64_t partial_bytes = 0;  // bytes at the end too few for a record (no end marker)
};

// Calls on_run(first value, records) for each streamline, values of type T in the stored byte
// order; each record is `Width` values.
template <class T, bool BigEndian, int Width, class OnRun>
TrackRuns walk_track_runs(std::string_view data, OnRun&& on_run) {
  constexpr size_t record = Width * sizeof(T);
  const size_t records = data.size() / record;
  TrackRuns r;
  size_t start = 0;
  const char* p = data.data();
  for (size_t i = 0; i < records; ++i, p += record) {
    bool all_nan = true, all_inf = true;
    for (int v = 0; v < Width; ++v) {
      const T value = load_stored<T, BigEndian>(p + v * sizeof(T));
      all_nan = all_nan && std::isnan(value);
      all_inf = all_inf && std::isinf(value);
    }
    if (all_nan) {
      if (i > start) {
        on_run(data.data() + start * record, i - start);
        ++r.runs;
        r.records += i - start;
      } else {
        ++r.empty;
      }
      start = i + 1;
    } else if (all_inf) {
      r.end_marker = true;
      r.unterminated = i - start;
      r.bytes_after = data.size() - (i + 1) * record;
      return r;
    }
  }
  r.unterminated = records - start;
  r.partial_bytes = data.size() - records * record;
  return r;
}

// Calls f(T{}, std::bool_constant<BigEndian>{}) for the file's value type.
template <class F>
decltype(auto) with_track_value_type(TrackValueType type, F&& f) {
  switch (type) {
    case TrackValueType::float32be:
      return f(float{}, std::true_type{});
    case TrackValueType::float64le:
      return f(double{}, std::false_type{});
    case TrackValueType::float64be:
      return f(double{}, std::true_type{});
    case TrackValueType::float32le:
    default:
      return f(float{}, std::false_type{});
  }
}

// The notes a walk's findings give ("no end marker", "bytes after it", "a streamline cut
// short"); `marker_expected`: whether a file without the marker is worth a note (.tck, where
// nibabel refuses it; MRtrix's .tsf files end without one).
void note_track_runs(const TrackRuns& runs, bool marker_expected, const std::string& what,
                     std::vector<std::string>& notes);

}  // namespace imx::detail
