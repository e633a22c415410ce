// One row per label-table format. A new format: its reader and one row here.
#include "labels/label_table_formats.hpp"

#include "labels/colour_table_readers.hpp"

namespace imx::labels_detail {
namespace {

constexpr std::string_view kNeedsLabels =
    "a label volume: its object's \"labels\": {\"table\": ...}";

bool nrrd_head(const detail::FileProbe& probe) {
  return looks_like_nrrd(probe.head);
}

}  // namespace

std::span<const LabelTableFormat> label_table_formats_table() {
  static const std::vector<LabelTableFormat> table = {
      {{.kind = detail::FileKind::label_table,
        .name = "3D Slicer segmentation",
        .extensions = {".seg.nrrd"},
        .sniff = nrrd_head,
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
