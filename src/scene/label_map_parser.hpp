// Parser for a label volume's "labels" block and "interpolation" (style "labels").
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "intermix/labels.hpp"
#include "intermix/volume.hpp"
#include "scene/json_reader.hpp"
#include "scene/scene_parsers.hpp"

namespace imx::scene_json {

// The label map of volume object `r`: its "labels" ({"file": ...} or {"table": [...]}, with an
// optional "unit_distance" and "overrides" [{"value", "visible", "opacity", "color"}] that change
// or add rows: the viewer's label edits), none for the default palette, and "interpolation"
// ("smooth" or "nearest"). `layer`: which layer of a 3D Slicer segmentation the volume holds (its
// frame). `visible` false hides every label. Throws imx::Error naming the JSON path or the table's
// file.
std::shared_ptr<const LabelMap> parse_label_map(const JsonReader& r, SceneContext& context,
                                                int layer, bool visible);

// How `map` draws label `value`: its row, else the default palette's colour (hidden for label 0,
// and for every unlisted label when a table was given), named "label N".
LabelEntry label_entry(const LabelMap& map, int32_t value);

// Throws imx::Error naming `what` unless every voxel is an integer label: float voxels must be
// finite integers within +-2^24 (exact in a sample's float arithmetic).
void check_label_voxels(const VolumeData& data, const std::string& what);

}  // namespace imx::scene_json
