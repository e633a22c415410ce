// Per-vertex overlays: values on a surface's vertices from FreeSurfer curv/thickness/sulc, .annot
// and .label files and GIfTI func/shape/label files, or a mesh file's point data.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

namespace imx::detail {

// One entry of a label overlay's colour table.
struct OverlayLabel {
  int64_t key = 0;  // the value vertices with this label have
  std::string name;
  glm::vec4 rgba{1.0f};  // display (sRGB) colour and opacity in [0, 1], as the file gives them
};

struct VertexOverlay {
  // One per vertex of the surface it belongs to; NaN where the file gives a vertex no value
  // (an .annot vertex with no label).
  std::vector<double> values;
  bool labels = false;              // values are keys of `table` (annot, GIfTI label, .label)
  std::vector<OverlayLabel> table;  // a label overlay's colour table
  // A .label's vertices, which have key 1 (values is then empty: every other vertex is NaN).
  std::vector<uint32_t> members;
  // Vertices the file claims: the surface it belongs to must have as many (0 for a .label,
  // which names only its own vertices: then every vertex it names must exist).
  uint64_t claimed_vertices = 0;
};

// The format by content and name: GIfTI (.gii, its first data array of intent NONE, SHAPE,
// LABEL or any statistic, or `array` when given), FreeSurfer curvature (magic 0xFFFFFF: curv,
// thickness, sulc, area, ...), .annot, .label. Throws imx::Error naming the file and the fault.
VertexOverlay read_vertex_overlay(const std::filesystem::path& file, int array = -1);

// Whether `file` holds per-vertex values rather than a surface: .annot or .label, FreeSurfer
// curvature (its magic), or a GIfTI file without a NIFTI_INTENT_POINTSET array. Reads at most
// the file's first bytes for the magic and scans a GIfTI file's text once.
bool is_overlay_file(const std::filesystem::path& file);

// The overlay's value at each of `vertex_count` vertices (a .label's members expanded): throws
// imx::Error "WHAT: the overlay has N values, the mesh M vertices" when the counts differ, or a
// .label names a vertex the mesh lacks.
std::vector<double> overlay_values(const VertexOverlay& overlay, size_t vertex_count,
                                   const std::string& what);

// A GIfTI func, shape or label file's data array `array` (-1: the first of intent NONE, SHAPE,
// LABEL or any statistic).
VertexOverlay read_gifti_vertex_overlay(const std::filesystem::path& file, int array);

// The FreeSurfer formats, one file each (freesurfer_curv.cpp, freesurfer_annot.cpp,
// freesurfer_label.cpp), on a file's bytes; `what` names it in errors.
bool is_freesurfer_curv(const std::string& bytes);
// New-format curvature as nibabel.freesurfer.read_morph_data reads it: magic, vertex count, face
// count, values per vertex (1), float32 values, all big-endian. The old 3-byte format is refused.
VertexOverlay read_freesurfer_curv(const std::string& bytes, const std::string& what);
// An annotation as nibabel.freesurfer.read_annot reads it: (vertex, packed RGB) pairs and a
// colour table (old or new, version 2, format); a vertex's value is the key of the table
// entry whose packed colour it holds (the entry's index), NaN for 0 (no label).
VertexOverlay read_freesurfer_annot(const std::string& bytes, const std::string& what);
// An ASCII label as nibabel.freesurfer.read_label reads it: a comment line, a count, then
// "vertex x y z value" lines; its vertices (members) get key 1, named `name`.
VertexOverlay read_freesurfer_label(const std::string& bytes, const std::string& what,
                                    const std::string& name);

}  // namespace imx::detail
