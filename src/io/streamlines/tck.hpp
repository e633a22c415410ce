// MRtrix tractograms (.tck) and their per-point scalars (.tsf), read as nibabel.streamlines.load
// reads .tck (mrtrix_tracks.hpp has the layout both share).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "intermix/streamlines.hpp"

namespace imx::detail {

// The streamlines of `file` in world LPS mm (the file's points are RAS mm: x and y negated).
// Float32 and Float64 in either byte order. Streamlines of fewer than 2 points, or with a
// coordinate that is not finite, are dropped and said in `notes`, as are a 'count' that differs
// from the streamlines the file holds (nibabel reads what it holds), a file without its end
// marker (read to its end, as MRtrix does; a last streamline without its delimiter is dropped)
// and bytes after the marker. Throws imx::Error naming the file and the field (see
// parse_mrtrix_track_header).
Streamlines read_tck(const std::filesystem::path& file, std::vector<std::string>& notes);

// Appends the values of the track scalar file `tsf` to `s` as a point_values array named after
// the file's stem. Its streamlines must be those of the tracks `s` was read from, point for
// point; where the tracks' reader dropped streamlines of fewer than 2 points, the TSF's of fewer
// than 2 values are skipped to match (a note says so). Throws imx::Error naming `tsf` and
// `tracks` (the tracks' file, for the message) when the counts differ, or as read_tck does.
void read_tsf(const std::filesystem::path& tsf, Streamlines& s, std::vector<std::string>& notes,
              const std::filesystem::path& tracks = "the tracks");

}  // namespace imx::detail
