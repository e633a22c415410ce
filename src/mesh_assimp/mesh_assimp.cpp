// The mesh plugin: assimp imports one mesh file (OBJ, STL, OFF, glTF; imx_io checks the file
// and chooses the format first) behind the C interface of mesh_assimp_abi.h. imx_io opens it on
// first use (io/mesh/mesh_assimp_plugin.cpp) and turns what it gives into an imx::Mesh.
#include "mesh_assimp/mesh_assimp_abi.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>
#include <glm/glm.hpp>

#include "core/colour.hpp"
#include "core/math.hpp"
#include "mesh_assimp/assimp_guard.hpp"

namespace {

// One imported file, between read and close.
struct Imported {
  Assimp::Importer importer;
  const aiScene* scene = nullptr;
  bool srgb_colors = true;
};

void set_error(char* error, size_t error_size, const std::string& message) {
  if (error != nullptr && error_size > 0) std::snprintf(error, error_size, "%s", message.c_str());
}

glm::dmat4 to_glm(const aiMatrix4x4& m) {
  glm::dmat4 out(1.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[c][r] = m[r][c];
  return out;
}

// Where copy writes; null pointers are skipped (a first pass only counts).
struct Sink {
  float* positions = nullptr;
  float* normals = nullptr;
  float* colors = nullptr;
  uint32_t* triangles = nullptr;
};

void put(float* to, uint64_t at, const glm::vec3& v) {
  to[3 * at] = v.x;
  to[3 * at + 1] = v.y;
  to[3 * at + 2] = v.z;
}

// Visits the triangles of every mesh in the node tree, in world (file) units. An explicit
// stack: a file's tree may be deep.
void collect(const aiScene& scene, bool srgb_colors, const Sink& sink,
             imx_mesh_assimp_counts& counts) {
  counts = {0, 0, 1, 1};
  std::vector<std::pair<const aiNode*, glm::dmat4>> stack{{scene.mRootNode, glm::dmat4(1.0)}};
  while (!stack.empty()) {
    auto [node, parent] = stack.back();
    stack.pop_back();
    const glm::dmat4 m = parent * to_glm(node->mTransformation);
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(m)));
    const bool mirrored = glm::determinant(glm::dmat3(m)) < 0.0;
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      if (node->mMeshes[k] >= scene.mNumMeshes) continue;
      const aiMesh& mesh = *scene.mMeshes[node->mMeshes[k]];
      const auto base = static_cast<uint32_t>(counts.vertices);
      counts.normals = counts.normals && mesh.HasNormals();
      counts.colors = counts.colors && mesh.HasVertexColors(0);
      if (sink.positions != nullptr) {
        for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
          const uint64_t at = counts.vertices + v;
          const aiVector3D& p = mesh.mVertices[v];
          put(sink.positions, at, glm::vec3(imx::transform_point(m, {p.x, p.y, p.z})));
          glm::dvec3 n(0.0);
          if (mesh.HasNormals()) {
            const aiVector3D& a = mesh.mNormals[v];
            n = normal_matrix * glm::dvec3(a.x, a.y, a.z);
            double len = glm::length(n);
            // assimp leaves NaN normals on degenerate faces: a zero normal means "none" to shading.
            n = (std::isfinite(len) && len > 0.0) ? n / len : glm::dvec3(0.0);
          }
          if (sink.normals != nullptr) put(sink.normals, at, glm::vec3(n));
          glm::vec3 color(1.0f);
          if (mesh.HasVertexColors(0)) {
            const aiColor4D& c = mesh.mColors[0][v];
            color = srgb_colors ? imx::display_to_linear(glm::vec3(c.r, c.g, c.b))
                                : glm::clamp(glm::vec3(c.r, c.g, c.b), 0.0f, 1.0f);
            if (!imx::all_finite(color)) color = glm::vec3(1.0f);
          }
          if (sink.colors != nullptr) put(sink.colors, at, color);
        }
      }
      counts.vertices += mesh.mNumVertices;
      for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines left by the importer
        if (sink.triangles != nullptr) {
          glm::uvec3 t(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
          if (mirrored) std::swap(t.y, t.z);
          uint32_t* to = sink.triangles + 3 * counts.triangles;
          to[0] = t.x;
          to[1] = t.y;
          to[2] = t.z;
        }
        ++counts.triangles;
      }
    }
    for (unsigned c = node->mNumChildren; c-- > 0;) stack.emplace_back(node->mChildren[c], m);
  }
}

int32_t read(const char* path, bool srgb_colors, imx_mesh_assimp_allow_fn allow, void* context,
             void** scene_out, imx_mesh_assimp_counts* counts, char* error, size_t error_size) {
  auto imported = std::make_unique<Imported>();
  imported->srgb_colors = srgb_colors;
  Assimp::Importer& importer = imported->importer;
  // assimp picks its OBJ reader by the extension, whatever its case.
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  importer.SetIOHandler(
      new imx::detail::GuardedIOSystem(path, extension == ".obj", allow, context));
  imx::detail::AssimpErrorLog errors;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // No GenSmoothNormals: imx_io computes missing normals the same way for every format.
  const unsigned flags =
      aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType;
  const aiScene* scene = importer.ReadFile(path, flags);
  if (scene == nullptr || scene->mRootNode == nullptr ||
      (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || !errors.first_error().empty()) {
    std::string why = scene == nullptr ? importer.GetErrorString() : errors.first_error();
    set_error(error, error_size, why.empty() ? "assimp returned no scene" : why);
    return IMX_MESH_ASSIMP_FAILED;
  }
  imported->scene = scene;
  collect(*scene, srgb_colors, Sink{}, *counts);
  *scene_out = imported.release();
  return IMX_MESH_ASSIMP_OK;
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) uint32_t imx_mesh_assimp_abi(void) {
  return IMX_MESH_ASSIMP_ABI_VERSION;
}

__attribute__((visibility("default"))) int32_t imx_mesh_assimp_read(
    const char* path, int32_t srgb_colors, imx_mesh_assimp_allow_fn allow, void* context,
    void** scene, imx_mesh_assimp_counts* counts, char* error, size_t error_size) {
  if (error != nullptr && error_size > 0) error[0] = '\0';
  *scene = nullptr;
  // Nothing thrown leaves the plugin: the caller is C.
  try {
    return read(path, srgb_colors != 0, allow, context, scene, counts, error, error_size);
  } catch (const std::bad_alloc&) {
    return IMX_MESH_ASSIMP_OUT_OF_MEMORY;
  } catch (const std::exception& e) {
    set_error(error, error_size, e.what());
    return IMX_MESH_ASSIMP_FAILED;
  } catch (...) {
    set_error(error, error_size, "assimp failed");
    return IMX_MESH_ASSIMP_FAILED;
  }
}

__attribute__((visibility("default"))) int32_t imx_mesh_assimp_copy(void* scene, float* positions,
                                                                    float* normals, float* colors,
                                                                    uint32_t* triangles) {
  const auto& imported = *static_cast<const Imported*>(scene);
  imx_mesh_assimp_counts counts{};
  try {  // the node stack is the one allocation
    collect(*imported.scene, imported.srgb_colors, Sink{positions, normals, colors, triangles},
            counts);
  } catch (...) {
    return IMX_MESH_ASSIMP_OUT_OF_MEMORY;
  }
  return IMX_MESH_ASSIMP_OK;
}

__attribute__((visibility("default"))) void imx_mesh_assimp_close(void* scene) {
  delete static_cast<Imported*>(scene);
}
}

// The definitions have the interface's signatures (imx_io calls them through these types).
[[maybe_unused]] constexpr imx_mesh_assimp_abi_fn imx_abi_signature = &imx_mesh_assimp_abi;
[[maybe_unused]] constexpr imx_mesh_assimp_read_fn imx_read_signature = &imx_mesh_assimp_read;
[[maybe_unused]] constexpr imx_mesh_assimp_copy_fn imx_copy_signature = &imx_mesh_assimp_copy;
[[maybe_unused]] constexpr imx_mesh_assimp_close_fn imx_close_signature = &imx_mesh_assimp_close;
