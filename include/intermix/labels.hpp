// Label maps: an integer volume whose voxels name tissues, drawn through a colour table
// ("style": "labels", docs/segmentations_overlays.md).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace imx {

// One row of a colour table.
struct LabelEntry {
  int32_t value = 0;
  std::string name;
  glm::vec3 color{1.0f};  // straight linear RGB in [0, 1]: tables' display colours, decoded
  float opacity = 1.0f;   // of unit_distance mm of the tissue, in [0, 1]
  bool visible = true;
};

// How a label volume is classified: by the labels' trilinearly interpolated indicator functions
// (smooth boundaries that show only the labels on either side), or by the nearest voxel.
enum class LabelInterpolation : uint8_t { smooth, nearest };

// A label volume's colour table and classification. Values absent from `entries` are hidden
// when `palette_unlisted` is false (a table was given), else drawn in the default palette
// (default_label_color); label 0 is background and hidden unless an entry shows it.
struct LabelMap {
  std::vector<LabelEntry> entries;  // values unique (validate_label_entries)
  bool palette_unlisted = true;
  LabelInterpolation interpolation = LabelInterpolation::smooth;
  double unit_distance = 1.0;  // mm of tissue the opacities refer to
  bool shown = true;           // false ("visible": false): no volume shows; planes still draw it
  std::string source;          // the table's file or "inline": for messages and the viewer
};

// The default palette's colour of label `value` (never 0), decoded to linear: 24 distinct display
// colours in turn, neighbouring values differing in hue and lightness (docs/colour.md).
glm::vec3 default_label_color(int32_t value);

// Reads a colour table file, by its content: FreeSurfer's LUT text (`No. Name R G B A`, A is
// transparency, 0 = opaque), an ITK-SNAP label description file (`IDX R G B A VIS MSH "name"`),
// or the segment fields of a 3D Slicer .seg.nrrd / .nrrd header (`SegmentN_Name`, `_Color`,
// `_LabelValue`, `_Layer`), whose segments of layer `layer` are returned. Throws imx::Error naming
// the file and line or field: a duplicate label, a malformed row, segment fields that disagree
// with each other or with the layers.
std::vector<LabelEntry> read_label_table(const std::filesystem::path& file, int layer = 0);

// Throws imx::Error naming `what` when two entries share a value, or a colour or opacity is
// outside [0, 1] or not finite.
void validate_label_entries(const std::vector<LabelEntry>& entries, const std::string& what);

}  // namespace imx
