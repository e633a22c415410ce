// CIFTI-2 dense files (.dscalar.nii, .dlabel.nii, .dtseries.nii): surface data in a NIfTI-2
// container, as nibabel.cifti2 reads it. The header's extension (ecode 32) holds XML with two
// index maps: brain models (which surface vertices, per structure, each data column is) and
// maps (named scalars, label maps with their tables, or a series of frames). A surface overlay
// takes one map of one surface structure; voxel models (subcortical grey matter) are skipped, as
// they have no surface to colour, and parcellated files (.pscalar, .ptseries) are refused.
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "io/overlay/vertex_overlay.hpp"
#include "io/voxels/raw_voxels.hpp"

namespace imx::detail {

// The most brainordinates and maps a file may declare (a 1 mm whole-brain grayordinate space has
// under 200,000; a long series some thousands of frames).
inline constexpr int64_t kMaxCiftiBrainordinates = int64_t{1} << 24;
inline constexpr int64_t kMaxCiftiMaps = int64_t{1} << 20;
// The most bytes of header extensions (the XML) read: a dense file's is a few MB.
inline constexpr uint64_t kMaxCiftiXmlBytes = uint64_t{256} << 20;

// One brain model: a stretch of brainordinates (data columns) on a surface structure or in
// voxels.
struct CiftiBrainModel {
  std::string structure;           // "CIFTI_STRUCTURE_CORTEX_LEFT", ...
  bool surface = false;            // CIFTI_MODEL_TYPE_SURFACE, else CIFTI_MODEL_TYPE_VOXELS
  int64_t offset = 0;              // IndexOffset: its first brainordinate
  int64_t count = 0;               // IndexCount
  int64_t surface_vertices = 0;    // SurfaceNumberOfVertices (surface models)
  std::vector<uint32_t> vertices;  // VertexIndices, one per brainordinate (surface models)
};

enum class CiftiMapKind { scalars, labels, series };

struct CiftiFile {
  std::filesystem::path file;
  int intent_code = 0;
  CiftiMapKind kind = CiftiMapKind::scalars;
  int64_t maps = 0;                                     // scalar maps, label maps or frames
  std::vector<std::string> map_names;                   // scalars and labels: MapName per map
  std::vector<std::vector<OverlayLabel>> label_tables;  // labels: the table of each map
  int64_t brainordinates = 0;
  std::vector<CiftiBrainModel> models;  // in IndexOffset order, covering every brainordinate
  // The data: a maps x brainordinates matrix (or its transpose) of `type` at `offset`.
  bool maps_fastest = true;  // the maps run along NIfTI dim[5] (matrix dimension 0), as usual
  RawType type = RawType::f32;
  bool swap = false;
  bool gzipped = false;
  uint64_t offset = 0;
  double slope = 0.0, inter = 0.0;  // NIfTI scaling, slope 0 for none
};

// Whether `file` is a NIfTI file whose intent is a CIFTI one (3000-3099). Reads the header only;
// false for anything it cannot read. is_cifti_head: the same on a file's first (at least 512,
// inflated) bytes.
bool is_cifti(const std::filesystem::path& file);
bool is_cifti_head(std::string_view head);

// The overlay of a CIFTI-2 file with one surface structure (map `map`, -1 for the first), as
// read_vertex_overlay gives it; several structures are refused (cifti_overlay picks one).
VertexOverlay read_cifti_vertex_overlay(const std::filesystem::path& file, int map);

// The header and XML of a CIFTI-2 file, every count checked against the file (the data's
// length too). Throws imx::Error naming the file and the field: for NIfTI-1 or CIFTI-1, a
// missing or unreadable XML extension, dense connectivity or parcels, brain models that do not
// tile the brainordinates, a vertex index past SurfaceNumberOfVertices or repeated, and data
// dimensions that disagree with the maps.
CiftiFile read_cifti(const std::filesystem::path& file);

// Map (or frame) `map` of surface structure `structure` (its full name, or without the
// "CIFTI_STRUCTURE_" prefix, in any case) on every one of the structure's
// SurfaceNumberOfVertices vertices: NaN where the file has no value (the medial wall). A label
// file's values are keys of the map's table. Throws imx::Error naming `what`, the structures
// there are, or the maps there are.
VertexOverlay cifti_overlay(const CiftiFile& cifti, const std::string& structure, int64_t map,
                            const std::string& what);

// The CIFTI structure of the surface in `surface` (a mesh file of `vertices` vertices) among
// `cifti`'s surface models: its GIfTI AnatomicalStructurePrimary (CortexLeft ->
// CIFTI_STRUCTURE_CORTEX_LEFT), else its file name (lh., .L., left...; rh., .R., right...),
// else the only surface model of that many vertices. Throws imx::Error saying why none fits.
std::string cifti_structure_of_surface(const CiftiFile& cifti, const std::filesystem::path& surface,
                                       size_t vertices);

// "CIFTI_STRUCTURE_CORTEX_LEFT" as "CORTEX_LEFT" (for messages and scene files).
std::string short_structure_name(const std::string& structure);

}  // namespace imx::detail
