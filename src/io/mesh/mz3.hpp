// Surfice's MZ3 meshes and per-vertex overlays (.mz3), as NiiVue and Surfice read them: raw or
// gzip-compressed, little-endian, a 16-byte header (magic 23117 "MZ", ATTR flags, face, vertex
// and private-byte counts), then faces (int32 x3), vertices (float32 x3), colours (uint8 RGBA)
// and layers of scalars (float32, or float64 with isDOUBLE), each as many as the header says;
// the number of scalar layers is what the rest of the data holds.
#pragma once
#include <filesystem>

#include "io/mesh/polydata.hpp"
#include "io/overlay/vertex_overlay.hpp"

namespace imx::detail {

// A file with faces and vertices: the mesh as stored (MNI/RAS coordinates: .space is
// MeshSpace::ras, the caller converts), its colours (display sRGB bytes decoded to linear RGB;
// alpha is not kept) and one point data array per scalar layer ("scalars", "scalars1", ...; the
// first is "ambient_occlusion" when ATTR's isAOMAP flag says so). Throws imx::Error naming the
// file and the fault: not MZ3, a future version (ATTR over 63), flags the format rules out,
// counts the data cannot hold, bytes left over, a face naming a vertex that does not exist, a
// vertex that is not finite, corrupt or truncated gzip data. A file of values alone is refused
// as an overlay that needs its surface.
PolyDataFile read_mz3_mesh(const std::filesystem::path& file);

// Scalar layer `layer` of an MZ3 file (-1: the first, past an ambient occlusion map where there
// is another) as a per-vertex overlay. A file that also stores colours is a template (Surfice):
// its scalars are region numbers, integers, each region of one colour, and become a label
// overlay whose table gives each region its colour. Files of colours without scalars are
// refused, since an overlay is values.
VertexOverlay read_mz3_overlay(const std::filesystem::path& file, int layer);

// Whether an MZ3 file holds values for another mesh's vertices (no faces): reads its header,
// through gzip when compressed. Throws imx::Error when it is not an MZ3 file.
bool mz3_is_overlay(const std::filesystem::path& file);

}  // namespace imx::detail
