// GIfTI surfaces (.gii), neuroimaging's mesh format.
#pragma once
#include <filesystem>

#include "intermix/mesh.hpp"

namespace imx::detail {

// Reads the first POINTSET (vertices) and TRIANGLE data arrays of a GIfTI file
// (read_gifti_arrays checks the whole file), in either index order and any byte order, as the
// file stores them: GIfTI coordinates are RAS (NIfTI's), and the caller converts them. The
// CoordinateSystemTransformMatrix is not applied: it maps the stored coordinates to another
// space (its TransformedSpace) for information, and FreeSurfer, Workbench and nibabel show the
// stored coordinates as they are, which is where the surface lies over its volume. Triangles
// naming a vertex that does not exist are an imx::Error naming the file.
Mesh read_gifti(const std::filesystem::path& file);

}  // namespace imx::detail
