// One row per label-table format. A new format: its reader and one row here.
#include "labels/label_table_formats.hpp"

#include <string>

#include "labels/colour_table_readers.hpp"

namespace imx::labels_detail {
namespace {

constexpr std::string_view kNeedsLabels =
    "a label volume: its object's \"labels\": {\"table\": ...}";

// A NRRD whose first bytes hold 3D Slicer's segment fields (any NRRD is read as one when named
// as a colour table: read_label_table).
bool segmentation_head(const detail::FileProbe& probe) {
  return looks_like_nrrd(probe.head) && probe.head.find("Segment0_") != std::string::npos;
}

}  // namespace

std::span<const LabelTableFormat> label_table_formats_table() {
  static const std::vector<LabelTableFormat> table = {
      {{.kind = detail::FileKind::label_table,
        .name = "3D Slicer segmentation",
        .extensions = {".seg.nrrd"},
        .sniff = segmentation_head,
        .fuzz_target = "fuzz_labels",
        .reference = "3D Slicer (vtkMRMLSegmentationStorageNode)",
        .needs = kNeedsLabels},
       read_slicer_segments},
      {{.kind = detail::FileKind::label_table,
        .name = "FreeSurfer colour LUT",
        .extensions = {".txt", ".ctbl"},
        .fuzz_target = "fuzz_labels",
        .reference = "FreeSurfer (FreeSurferColorLUT.txt), nibabel",
        .needs = kNeedsLabels},
       read_text_table},
      {{.kind = detail::FileKind::label_table,
        .name = "ITK-SNAP label description",
        .extensions = {".txt"},
        .fuzz_target = "fuzz_labels",
        .reference = "ITK-SNAP",
        .needs = kNeedsLabels},
       read_text_table},
  };
  return table;
}

}  // namespace imx::labels_detail
