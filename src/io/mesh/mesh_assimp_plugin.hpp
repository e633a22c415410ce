// The mesh plugin (src/mesh_assimp/, libimx_mesh_assimp.so), opened with dlopen on the first
// mesh file of a format intermix does not parse itself (OBJ, STL, OFF, glTF): nothing else loads
// assimp, draco and minizip, which cost every start-up several milliseconds of relocation.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "intermix/mesh.hpp"

namespace imx::detail {

// Where the plugin is looked for, in order: $IMX_MESH_PLUGIN alone when it is set; else beside
// the program or module as installed (BINDIR/../LIBDIR/intermix), the install prefix's LIBDIR,
// and the build tree.
std::vector<std::string> mesh_plugin_paths();

// Imports `file` with assimp through the plugin (which is loaded once per process, thread-safe):
// positions, triangles, and normals and colours when every mesh of the file has them (colours
// sRGB-decoded when `srgb_colors`). Throws imx::Error "FILE: cannot read the mesh: ..." when
// assimp fails, "FILE: ... the mesh plugin cannot be loaded (tried: PATH (why), ...)" when no
// path gives a plugin of this build's interface version, std::bad_alloc when memory runs out.
Mesh import_mesh_with_plugin(const std::filesystem::path& file, bool srgb_colors);

}  // namespace imx::detail
