// A pre-check of STL files before assimp reads them: a binary file must hold the triangles its
// count says, an ASCII file must hold whole triangles; assimp's own words for these name its
// internals ("Failed to determine STL storage representation").
#pragma once
#include <filesystem>

namespace imx::detail {

// Throws imx::Error naming the file, the count and the size: a binary STL shorter than 84 + 50 x
// its triangle count, or of no triangles; an ASCII STL ("solid" ... "facet") whose
// vertex lines are not whole triangles, or none.
void check_stl(const std::filesystem::path& file);

}  // namespace imx::detail
