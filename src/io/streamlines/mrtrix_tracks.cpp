#include "io/streamlines/mrtrix_tracks.hpp"

#include <charconv>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {
namespace {

// Python's str.strip() for ASCII text.
std::string_view strip(std::string_view s) {
  const char* blanks = " \t\r\n\v\f";
  const size_t b = s.find_first_not_of(blanks);
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(blanks) - b + 1);
}

TrackValueType value_type(std::string_view datatype, const std::string& what) {
  const std::string t = lower(datatype);
  // nibabel reads a bare "Float32" as little-endian.
  if (t == "float32le" || t == "float32") return TrackValueType::float32le;
  if (t == "float32be") return TrackValueType::float32be;
  if (t == "float64le") return TrackValueType::float64le;
  if (t == "float64be") return TrackValueType::float64be;
  throw Error(
      fmt::format("{}: datatype '{}' (Float32LE, Float32BE, Float64LE and Float64BE are "
                  "read)",
                  what, shown(datatype)));
}

}  // namespace

MrtrixTrackFile parse_mrtrix_track_header(std::string_view bytes, std::string_view magic,
                                          const std::string& what,
                                          std::vector<std::string>& notes) {
  if (!bytes.starts_with(magic))
    throw Error(fmt::format("{}: not an MRtrix file of this kind (it does not start with '{}')",
                            what, magic));
  MrtrixTrackFile f;
  // nibabel skips the one byte after the magic (its newline), whatever it is.
  size_t at = std::min(bytes.size(), magic.size() + 1);
  bool found_end = false;
  int line_number = 1;
  std::string* last = nullptr;
  while (at < bytes.size() && at < kMaxHeaderBytes) {
    size_t eol = bytes.find('\n', at);
    if (eol == std::string_view::npos) eol = bytes.size();
    const std::string_view line = strip(bytes.substr(at, eol - at));
    at = std::min(eol + 1, bytes.size());
    ++line_number;
    if (line.empty()) continue;
    if (line == "END") {
      found_end = true;
      break;
    }
    const size_t colon = line.find(':');
    if (colon == std::string_view::npos) {
      if (last == nullptr)
        throw Error(fmt::format("{}: header line {} '{}' comes before any 'key: value' line", what,
                                line_number, shown(line)));
      *last += '\n';
      *last += line;
      continue;
    }
    const std::string key(strip(line.substr(0, colon)));
    const std::string value(strip(line.substr(colon + 1)));
    last = nullptr;
    for (auto& [k, v] : f.fields)
      if (k == key) {
        v += '\n' + value;
        last = &v;
      }
    if (last == nullptr) last = &f.fields.emplace_back(key, value).second;
  }
  if (!found_end)
    throw Error(fmt::format("{}: no END line ends the header{}", what,
                            at >= kMaxHeaderBytes ? " in its first MiB" : ""));
  const size_t header_end = at;

  if (const std::string* datatype = f.field("datatype")) {
    f.type = value_type(*datatype, what);
  } else {
    notes.push_back(fmt::format("{}: no datatype in the header: Float32LE assumed", what));
  }

  size_t offset = header_end;
  if (const std::string* file = f.field("file")) {
    const std::vector<std::string_view> words = split_words(*file);
    if (words.size() < 2 || words[0] != ".")
      throw Error(
          fmt::format("{}: file '{}' is not '. OFFSET' (the data in this file, from byte "
                      "OFFSET)",
                      what, shown(*file)));
    const std::optional<uint64_t> parsed = parse_header_number<uint64_t>(words[1]);
    if (!parsed || *parsed > bytes.size())
      throw Error(fmt::format("{}: file offset '{}' is not a byte of the file ({} bytes)", what,
                              shown(words[1]), bytes.size()));
    if (*parsed < header_end)
      throw Error(fmt::format("{}: file offset {} lies inside the header, which ends at byte {}",
                              what, *parsed, header_end));
    offset = static_cast<size_t>(*parsed);
  } else {
    notes.push_back(
        fmt::format("{}: no 'file' in the header: the data taken to start after END", what));
  }
  f.data = bytes.substr(offset);
  return f;
}

void note_track_runs(const TrackRuns& runs, bool marker_expected, const std::string& what,
                     std::vector<std::string>& notes) {
  if (runs.empty > 0)
    notes.push_back(
        fmt::format("{}: {} empty streamline{} (a delimiter after a delimiter) "
                    "skipped, as nibabel does",
                    what, runs.empty, runs.empty == 1 ? "" : "s"));
  if (runs.unterminated > 0)
    notes.push_back(
        fmt::format("{}: the last {} point{} are not ended by a NaN delimiter (a cut "
                    "short streamline): dropped",
                    what, runs.unterminated, runs.unterminated == 1 ? "" : "s"));
  if (runs.end_marker && runs.bytes_after > 0)
    notes.push_back(
        fmt::format("{}: {} bytes after the end marker (inf inf inf) ignored, as "
                    "MRtrix does",
                    what, runs.bytes_after));
  if (!runs.end_marker && runs.partial_bytes > 0)
    notes.push_back(
        fmt::format("{}: the file ends {} bytes into a point (truncated?): they are "
                    "ignored",
                    what, runs.partial_bytes));
  if (!runs.end_marker && marker_expected)
    notes.push_back(
        fmt::format("{}: no end marker (inf inf inf): read to the end of the file, "
                    "as MRtrix does",
                    what));
}

}  // namespace imx::detail
