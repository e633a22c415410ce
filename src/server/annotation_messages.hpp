// The viewer's measurement messages (docs/viewer.md, "Measurements"): `annotations`, which
// replaces the scene's annotations with one document edit (so undo, save and every client see
// it), and `measure`, which answers what annotations measure: lengths, angles, and ROI
// statistics computed here over the volume's voxels in world space.
#pragma once
#include <nlohmann/json.hpp>

#include "server/viewer_state.hpp"

namespace imx::server {

// An `annotations` message: {"annotations": [{"kind", "points" (LPS, as the page sees the
// scene), "volume", "label"}, ...]} becomes the document's "annotations" (in its own space; an
// empty list removes the key). Throws imx::Error naming the field at fault (as the scene parser
// checks it: kind, point count, non-finite or far points, degenerate geometry, caps) and then
// leaves the state unchanged. Returns whether the document changed.
bool apply_annotations(ViewerState& state, const nlohmann::json& message);

// A `measure` message: {"annotations": [...]} (as above, at most kMaxMeasuredAnnotations) ->
// {"type": "measure", "seq", "measurements": [measurement_json, ...], "ms"}.
nlohmann::json answer_measure(const ViewerState& state, const nlohmann::json& message);
inline constexpr size_t kMaxMeasuredAnnotations = 64;

// A `pick` message: {"x", "y", "width", "height"}: a point of the 3-D view, in pixels of a view
// of that size through the session's camera -> {"type": "pick", "seq", "point" ([3], LPS, or
// null where no shown object is hit), "object"}: where the ray through it first meets a shown
// object (first_hit_depth: a volume where it alone reaches half opacity, the nearest surface), the
// nearest of them. The ray alone is traced: a 1x1 image through the pixel's centre.
nlohmann::json answer_pick(const ViewerState& state, const nlohmann::json& message);

// The document's annotations as describe_state sends them: points in LPS.
nlohmann::json annotations_json(const std::vector<Annotation>& annotations);

}  // namespace imx::server
