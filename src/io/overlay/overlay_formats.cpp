// One row per surface-overlay format. A new format: its reader file and one row here
// (docs/architecture.md).
#include "io/overlay/overlay_formats.hpp"

#include <fstream>
#include <iterator>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/mesh/mz3.hpp"
#include "io/overlay/cifti.hpp"
#include "io/streams/byte_cursor.hpp"
#include "io/streams/input_file.hpp"

namespace imx::detail {
namespace {

constexpr std::string_view kNeedsSurface = "the surface it colours, given before it";

void require_no_array(const std::filesystem::path& file, int array) {
  if (array >= 0)
    throw Error(fmt::format("{}: \"array\" picks a data array of a GIfTI file; this is not one",
                            file.string()));
}

bool curv_head(const FileProbe& probe) {
  return is_freesurfer_curv(probe.head);
}

// Surfice's MZ3 (raw or gzip: the probe's bytes are inflated) without faces: values only.
bool mz3_values_head(const FileProbe& probe) {
  return probe.head.size() >= 4 && probe.head.starts_with("MZ") &&
         (static_cast<uint8_t>(probe.head[2]) & 1) == 0;
}

// GIfTI is XML: a surface names NIFTI_INTENT_POINTSET; func, shape and label files do not.
bool gifti_data(const FileProbe& probe) {
  if (!probe.name.ends_with(".gii")) return false;
  std::ifstream in = try_open_input_stream(probe.path);
  if (!in) return false;
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  return text.find("NIFTI_INTENT_POINTSET") == std::string::npos;
}

VertexOverlay curv(const std::filesystem::path& file, int array) {
  require_no_array(file, array);
  return read_freesurfer_curv(read_file_bytes(file), file.string());
}

VertexOverlay annot(const std::filesystem::path& file, int array) {
  require_no_array(file, array);
  return read_freesurfer_annot(read_file_bytes(file), file.string());
}

VertexOverlay label(const std::filesystem::path& file, int array) {
  require_no_array(file, array);
  return read_freesurfer_label(read_file_bytes(file), file.string(), file.stem().string());
}

}  // namespace

std::span<const OverlayFormat> overlay_formats_table() {
  static const std::vector<OverlayFormat> table = {
      {{.kind = FileKind::overlay,
        .name = "FreeSurfer morphometry (curv, thickness, sulc, area)",
        .extensions = {".curv", ".thickness", ".sulc", ".area", ".avg_curv", ".jacobian_white"},
        .sniff = curv_head,
        .fuzz_target = "fuzz_surface",
        .reference = "nibabel.freesurfer.read_morph_data",
        .needs = kNeedsSurface},
       curv},
      {{.kind = FileKind::overlay,
        .name = "FreeSurfer annotation",
        .extensions = {".annot"},
        .fuzz_target = "fuzz_surface",
        .reference = "nibabel.freesurfer.read_annot",
        .needs = kNeedsSurface},
       annot},
      {{.kind = FileKind::overlay,
        .name = "FreeSurfer label",
        .extensions = {".label"},
        .fuzz_target = "fuzz_surface",
        .reference = "nibabel.freesurfer.read_label",
        .needs = kNeedsSurface},
       label},
      {{.kind = FileKind::overlay,
        .name = "GIfTI data (func, shape, label)",
        .extensions = {".func.gii", ".shape.gii", ".label.gii"},
        .sniff = gifti_data,
        .fuzz_target = "fuzz_surface",
        .reference = "nibabel",
        .needs = kNeedsSurface},
       read_gifti_vertex_overlay},
      {{.kind = FileKind::overlay,
        .name = "CIFTI-2 dense data (scalars, labels, series)",
        .extensions = {".dscalar.nii", ".dlabel.nii", ".dtseries.nii"},
        .sniff = [](const FileProbe& probe) { return is_cifti_head(probe.head); },
        .fuzz_target = "fuzz_cifti",
        .fuzz_seeds = "*.dscalar.nii",
        .reference = "nibabel.cifti2",
        .needs = kNeedsSurface},
       read_cifti_vertex_overlay},
      {{.kind = FileKind::overlay,
        .name = "Surfice/NiiVue MZ3 values",
        .sniff = mz3_values_head,
        .fuzz_target = "fuzz_mz3",
        .reference = "NiiVue (readMZ3), Surfice",
        .needs = kNeedsSurface},
       read_mz3_overlay},
  };
  return table;
}

const OverlayFormat* find_overlay_format(const FileProbe& probe) {
  return find_format(overlay_formats_table(), probe);
}

}  // namespace imx::detail
