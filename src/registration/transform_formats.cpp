// One row per transform format. A new format: its reader and one row here.
#include "registration/transform_formats.hpp"

#include <vector>

#include "registration/transform_readers.hpp"

namespace imx::detail {
namespace {

constexpr std::string_view kNeedsObject =
    "an object to place: a scene object's \"transform\": {\"file\": ...}";

bool itk_text_head(const FileProbe& probe) {
  std::string_view bytes = probe.head;
  while (!bytes.empty() && (bytes.front() == ' ' || bytes.front() == '\n' ||
                            bytes.front() == '\r' || bytes.front() == '\t'))
    bytes.remove_prefix(1);
  return bytes.starts_with("#Insight Transform File");
}

// A .mat is ITK's binary (MATLAB v4 or v5) or FSL's text matrix: told apart by content.
bool matlab_head(const FileProbe& probe) {
  return probe.name.ends_with(".mat") &&
         (looks_like_matlab_v4(probe.head) || probe.head.starts_with("MATLAB"));
}

}  // namespace

std::span<const TransformFileFormat> transform_formats_table() {
  static const std::vector<TransformFileFormat> table = {
      {{.kind = FileKind::transform,
        .name = "ITK text transform (ITK, 3D Slicer, ANTs)",
        .extensions = {".tfm", ".txt"},
        .sniff = itk_text_head,
        .fuzz_target = "fuzz_transform",
        .reference = "ITK (itk::TransformFileReader)",
        .needs = kNeedsObject},
       TransformFormat::itk_text},
      {{.kind = FileKind::transform,
        .name = "ITK binary transform (MATLAB v4)",
        .extensions = {},
        .sniff = matlab_head,
        .fuzz_target = "fuzz_transform",
        .reference = "ITK (itk::TransformFileReader)",
        .needs = kNeedsObject},
       TransformFormat::itk_matlab},
      {{.kind = FileKind::transform,
        .name = "FSL FLIRT matrix",
        .extensions = {".mat"},
        .fuzz_target = "fuzz_transform",
        .reference = "FSL (img2imgcoord)",
        .needs = kNeedsObject},
       TransformFormat::fsl_flirt},
      {{.kind = FileKind::transform,
        .name = "FreeSurfer LTA",
        .extensions = {".lta"},
        .fuzz_target = "fuzz_transform",
        .reference = "FreeSurfer (lta_convert)",
        .needs = kNeedsObject},
       TransformFormat::freesurfer_lta},
      {{.kind = FileKind::transform,
        .name = "AFNI aff12 matrix",
        .extensions = {".1d"},
        .fuzz_target = "fuzz_transform",
        .reference = "AFNI (cat_matvec)",
        .needs = kNeedsObject},
       TransformFormat::afni_aff12},
  };
  return table;
}

}  // namespace imx::detail
