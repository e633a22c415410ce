// The colour-table formats read_label_table dispatches to, each from the file's text.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "intermix/labels.hpp"

namespace imx::labels_detail {

// FreeSurfer's LUT text (FreeSurferColorLUT.txt): rows `No. Name R G B A`, colours 0-255, A the
// transparency (0 = opaque). `what` names the file in errors.
std::vector<LabelEntry> parse_freesurfer_lut(std::string_view text, const std::string& what);

// ITK-SNAP's label description file: rows `IDX R G B A VIS MSH "name"`, colours 0-255, A the
// opacity in [0, 1] (ITK-SNAP writes 1 for opaque labels), VIS 0 or 1; MSH is not read.
std::vector<LabelEntry> parse_itksnap_labels(std::string_view text, const std::string& what);

// The `key:=value` fields of a NRRD header (3D Slicer's .seg.nrrd), in file order.
struct NrrdKeyValue {
  std::string key, value;
  int line = 0;
};

// The segments of layer `layer` of a Slicer segmentation, from its header's key/value fields and
// its number of layers (the file's frames: 1 for a 3-D file).
std::vector<LabelEntry> parse_slicer_segments(const std::vector<NrrdKeyValue>& fields, int layers,
                                              int layer, const std::string& what);

// The key/value fields of a NRRD header given as text (up to the blank line ending it).
std::vector<NrrdKeyValue> nrrd_key_values(std::string_view header, const std::string& what);

// Whether `text` begins as a NRRD header does ("NRRD000").
inline bool looks_like_nrrd(std::string_view text) {
  return text.rfind("NRRD000", 0) == 0;
}

}  // namespace imx::labels_detail
