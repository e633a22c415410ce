// Checks a glTF 2 file (.gltf or .glb) before assimp reads it: assimp trusts the sizes and
// links in the file, so a 20-byte .glb can make it allocate gigabytes, and a deep or cyclic
// node tree overflows its recursion.
#pragma once
#include <filesystem>

namespace imx::detail {

// Throws imx::Error naming the file and the field at fault: GLB chunk lengths beyond the file,
// JSON nested deeper than 256 levels, node children out of range, shared, cyclic or deeper
// than 1024 levels, buffers, views and accessors larger than what holds them or than the memory
// budget (check_memory).
void check_gltf(const std::filesystem::path& file);

}  // namespace imx::detail
