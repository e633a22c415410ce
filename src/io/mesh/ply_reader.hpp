// PLY mesh files: read by hand because Debian 12's assimp (5.2.5) hangs or crashes on malformed
// ones.
#pragma once
#include <filesystem>

#include "intermix/mesh.hpp"

namespace imx::detail {

// Reads a PLY file (ascii, binary little- or big-endian): vertex x/y/z, optional nx/ny/nz and
// red/green/blue (sRGB, made linear; alpha is skipped), faces from the "vertex_indices" (or
// "vertex_index") list, fan-triangulated; other elements and properties are skipped. Normals
// and colours are left empty when the file has none. Every count,
// index and byte is checked, so a malformed file gives an imx::Error naming it and the fault.
Mesh read_ply(const std::filesystem::path& file);

}  // namespace imx::detail
