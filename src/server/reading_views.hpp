// The viewer's 2-D reading views (docs/viewer.md, "Reading views"): the answers to `slice`
// (one axial, coronal or sagittal image of every shown volume through a point, with the shown
// meshes' outlines) and `probe` (each volume's value at a point, in its units) messages.
#pragma once
#include <string>

#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>

#include "server/viewer_state.hpp"

namespace imx::server {

struct SliceAnswer {
  std::string text;  // {"type": "slice", "view", "seq", "point", "mm_per_pixel", "slab", ...}
  std::string png;   // the image: PNG, or JPEG when the message asked for "format": "jpeg"
};

// A `slice` message: {"view": "axial"|"coronal"|"sagittal", "point": [3], "width", "height",
// "mm_per_pixel", "seq", "window" (optional [centre, width] of the first shown volume, instead of
// its own volume_window: a W/L drag in progress), "slab" (optional, mm: the shown streamlines
// within half of it of the plane are drawn over the slice; default kDefaultStreamlineSlab),
// "format" (optional: "png", the default, or "jpeg" while a drag goes on), "rotation" (optional
// 3 x 3 rows: the crosshair's rotation, an oblique view; slice_orientation.hpp), "thick_slab"
// (optional {"thickness": mm, "mode": "mip"|"minip"|"mean"}: a thick-slab projection)}. The
// answer gives the view's unit "right", "down" and "normal" in LPS. Throws imx::Error naming the
// field at fault.
SliceAnswer answer_slice(const ViewerState& state, const nlohmann::json& message);

// A `probe` message: {"point": [3]} -> {"type": "probe", "point", "values": [{"name", "value"
// (the nearest voxel's; null outside the grid), "sample" (trilinear, as a view samples it; absent
// outside), "units", "index" [i, j, k]}, ...]} for every volume.
nlohmann::json answer_probe(const ViewerState& state, const nlohmann::json& message);

}  // namespace imx::server
