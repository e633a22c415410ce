// The window a volume is first shown through in 2-D (the viewer's reading views and reading
// planes; the figures' anatomy window): the header's own (DICOM WindowCenter/Width) when it
// shows the anatomy, else a robust range of the anatomy's values, with a note saying why.
#pragma once
#include <optional>
#include <string>

#include <glm/vec2.hpp>

#include "intermix/volume.hpp"

namespace imx {

// The header's window is kept when at least this fraction of the voxels above the background
// lie inside it.
inline constexpr double kHeaderWindowMinFraction = 0.2;

struct InitialWindow {
  glm::dvec2 window{0.0, 1.0};   // centre, width (> 0)
  bool from_header = false;      // the header's window, kept
  double background = 0.0;       // voxels at or below this value are background
  double header_fraction = 0.0;  // of the voxels above the background, inside the header's window
  std::string note;              // why the header's window was not used; empty when it was
};

// The rule, on a regular subsample of at most about a million finite voxels:
// - background: the voxels at the data's minimum (CT padding at -3024 or -2048, MR zero fill),
//   and of the others those at or below p1 + 10% of (p99 - p1), their 1st and 99th percentiles
//   (CT air at -1000 below tissue, MR noise below tissue); when that leaves nothing, only the
//   minimum is background, and a constant volume has none;
// - the header's window [centre - width/2, centre + width/2] when it holds at least
//   kHeaderWindowMinFraction of the voxels above the background;
// - else (or with no header window) the 2nd to 98th percentile of those voxels, with a note
//   when a header window was refused. A volume without a finite voxel gets [0, 1].
InitialWindow initial_display_window(const VolumeData& data,
                                     const std::optional<glm::dvec2>& header_window);

}  // namespace imx
