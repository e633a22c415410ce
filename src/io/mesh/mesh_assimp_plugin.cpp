#include "io/mesh/mesh_assimp_plugin.hpp"

#include <cstdio>
#include <exception>
#include <mutex>
#include <new>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/registry/plugin_loader.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"
#include "mesh_assimp/mesh_assimp_abi.h"

// CMake defines these on this file's command line only (CMakeLists.txt), so that no other
// compile names the build or install folder.
#ifndef IMX_MESH_PLUGIN_BUILT
#define IMX_MESH_PLUGIN_BUILT ""
#endif
#ifndef IMX_MESH_PLUGIN_INSTALLED
#define IMX_MESH_PLUGIN_INSTALLED ""
#endif
#ifndef IMX_MESH_PLUGIN_FROM_BINDIR
#define IMX_MESH_PLUGIN_FROM_BINDIR ""
#endif

namespace imx::detail {

namespace {

constexpr PluginPlace kPlace{"an intermix mesh plugin",   "IMX_MESH_PLUGIN",
                             IMX_MESH_PLUGIN_FROM_BINDIR, IMX_MESH_PLUGIN_INSTALLED,
                             IMX_MESH_PLUGIN_BUILT,       IMX_MESH_ASSIMP_ABI_SYMBOL,
                             IMX_MESH_ASSIMP_ABI_VERSION};

struct MeshPlugin {
  imx_mesh_assimp_read_fn read = nullptr;
  imx_mesh_assimp_copy_fn copy = nullptr;
  imx_mesh_assimp_close_fn close = nullptr;
};

const MeshPlugin& mesh_plugin(const std::filesystem::path& file) {
  // A failure is not kept: a later file tries again (IMX_MESH_PLUGIN may have been set since).
  static std::mutex mutex;
  static MeshPlugin loaded;
  std::lock_guard lock(mutex);
  if (loaded.read != nullptr) return loaded;
  std::string tried;
  if (void* handle = open_plugin(kPlace, tried)) {
    MeshPlugin p{reinterpret_cast<imx_mesh_assimp_read_fn>(
                     plugin_symbol(handle, IMX_MESH_ASSIMP_READ_SYMBOL)),
                 reinterpret_cast<imx_mesh_assimp_copy_fn>(
                     plugin_symbol(handle, IMX_MESH_ASSIMP_COPY_SYMBOL)),
                 reinterpret_cast<imx_mesh_assimp_close_fn>(
                     plugin_symbol(handle, IMX_MESH_ASSIMP_CLOSE_SYMBOL))};
    if (p.read != nullptr && p.copy != nullptr && p.close != nullptr) return loaded = p;
    tried = "a plugin without " IMX_MESH_ASSIMP_READ_SYMBOL ", copy or close";
  }
  throw Error(fmt::format(
      "{}: reading this mesh format needs the mesh plugin, which cannot be loaded (tried: {}); "
      "set IMX_MESH_PLUGIN to the path of libimx_mesh_assimp.so",
      file.string(), tried));
}

// The plugin asks before assimp opens any other file than the mesh: the rules for data files.
int32_t allow_data_file(void* context, const char* path, char* error, size_t error_size) {
  try {
    resolve_data_file(*static_cast<const std::filesystem::path*>(context), path,
                      "a file it refers to");
    return 0;
  } catch (const std::exception& e) {
    std::snprintf(error, error_size, "%s", e.what());
  } catch (...) {
    std::snprintf(error, error_size, "%s", "refused");
  }
  return 1;
}

// Closes the plugin's scene however the copy ends.
struct SceneCloser {
  imx_mesh_assimp_close_fn close;
  void* scene;
  ~SceneCloser() {
    if (scene != nullptr) close(scene);
  }
};

}  // namespace

std::vector<std::string> mesh_plugin_paths() {
  return plugin_paths(kPlace);
}

Mesh import_mesh_with_plugin(const std::filesystem::path& file, bool srgb_colors) {
  // assimp opens by name and picks its reader by the extension: the guard checks the file first.
  open_input(file);
  const MeshPlugin& plugin = mesh_plugin(file);
  void* scene = nullptr;
  imx_mesh_assimp_counts counts{};
  char error[16384] = "";
  const int32_t status =
      plugin.read(file.string().c_str(), srgb_colors ? 1 : 0, &allow_data_file,
                  const_cast<std::filesystem::path*>(&file), &scene, &counts, error, sizeof error);
  SceneCloser closer{plugin.close, scene};
  if (status == IMX_MESH_ASSIMP_OUT_OF_MEMORY) throw std::bad_alloc();
  if (status != IMX_MESH_ASSIMP_OK || scene == nullptr)
    throw Error(fmt::format("{}: cannot read the mesh: {}", file.string(),
                            error[0] != '\0' ? error : "assimp returned no scene"));
  Mesh mesh;
  mesh.positions.resize(counts.vertices);
  if (counts.normals) mesh.normals.resize(counts.vertices);
  if (counts.colors) mesh.colors.resize(counts.vertices);
  mesh.triangles.resize(counts.triangles);
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float) &&
                sizeof(glm::uvec3) == 3 * sizeof(uint32_t));
  auto floats = [](std::vector<glm::vec3>& v) {
    return v.empty() ? nullptr : reinterpret_cast<float*>(v.data());
  };
  if (plugin.copy(
          scene, floats(mesh.positions), floats(mesh.normals), floats(mesh.colors),
          mesh.triangles.empty() ? nullptr : reinterpret_cast<uint32_t*>(mesh.triangles.data())) !=
      IMX_MESH_ASSIMP_OK)
    throw std::bad_alloc();
  return mesh;
}

}  // namespace imx::detail
