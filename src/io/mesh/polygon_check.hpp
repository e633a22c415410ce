// Pre-checks of the polygon formats assimp reads (OBJ, OFF): its triangulation is quadratic in
// a polygon's corners, and its OFF reader clamps or wraps bad indices instead of failing.
#pragma once
#include <filesystem>

namespace imx::detail {

// At most this many corners in one polygon.
inline constexpr size_t kMaxPolygonCorners = 1024;
// The most corners assimp's OFF reader takes in a face.
inline constexpr size_t kMaxOffCorners = 9;

// Throws imx::Error naming the file and line when an OBJ face has more than kMaxPolygonCorners
// corners or names a vertex the file does not have, a line holds a NUL byte, an mtllib names an
// absolute path (assimp would look for it inside the OBJ's folder), or the file has no vertices
// or no faces (assimp's own words for these are its internals').
void check_obj_polygons(const std::filesystem::path& file);

// Throws imx::Error naming the file and face for an OFF file whose counts, corner counts or
// vertex indices are malformed or out of range.
void check_off(const std::filesystem::path& file);

}  // namespace imx::detail
