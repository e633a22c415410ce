#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <assimp/Importer.hpp>
#include <glm/glm.hpp>

#include "core/limits.hpp"
#include "core/math.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/assimp_guard.hpp"
#include "io/gltf_check.hpp"
#include "io/header_text.hpp"
#include "io/mesh_primitives.hpp"
#include "io/ply_reader.hpp"
#include "io/polygon_check.hpp"
#include "io/regular_file.hpp"

namespace imx {
namespace {

glm::dmat4 to_glm(const aiMatrix4x4& m) {
  glm::dmat4 out(1.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[c][r] = m[r][c];
  return out;
}

// Appends the triangles of every mesh in the node tree, in world (file) units. An explicit
// stack: a file's tree may be deep.
void collect(const aiScene& scene, Mesh& out, bool& all_have_normals) {
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
      const auto base = static_cast<uint32_t>(out.positions.size());
      all_have_normals = all_have_normals && mesh.HasNormals();
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
        const aiVector3D& p = mesh.mVertices[v];
        out.positions.emplace_back(transform_point(m, {p.x, p.y, p.z}));
        glm::dvec3 n(0.0);
        if (mesh.HasNormals()) {
          const aiVector3D& a = mesh.mNormals[v];
          n = normal_matrix * glm::dvec3(a.x, a.y, a.z);
          double len = glm::length(n);
          // assimp leaves NaN normals on degenerate faces: a zero normal means "none" to shading.
          n = (std::isfinite(len) && len > 0.0) ? n / len : glm::dvec3(0.0);
        }
        out.normals.emplace_back(n);
      }
      for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines left by the importer
        glm::uvec3 t(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
        if (mirrored) std::swap(t.y, t.z);
        out.triangles.push_back(t);
      }
    }
    for (unsigned c = node->mNumChildren; c-- > 0;) stack.emplace_back(node->mChildren[c], m);
  }
}

// PLY by extension or by its first line, whatever the extension says.
bool is_ply(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".ply") return true;
  char head[5] = {};
  std::ifstream(file, std::ios::binary).read(head, sizeof head);
  return std::memcmp(head, "ply", 3) == 0 && (head[3] == '\n' || head[3] == '\r');
}

// The formats assimp reads for intermix, by extension (others are refused rather than handed
// to one of assimp's forty importers).
constexpr const char* kAssimpFormats[] = {".obj", ".stl", ".off", ".gltf", ".glb"};

Mesh read_with_assimp(const std::filesystem::path& file) {
  const std::string ext = detail::lower(file.extension().string());
  if (std::find(std::begin(kAssimpFormats), std::end(kAssimpFormats), ext) ==
      std::end(kAssimpFormats))
    throw Error(fmt::format("{}: '{}' is not a mesh format intermix reads (it reads .ply, {})",
                            file.string(), ext, fmt::join(kAssimpFormats, ", ")));
  if (ext == ".gltf" || ext == ".glb") detail::check_gltf(file);
  if (ext == ".obj") detail::check_obj_polygons(file);
  if (ext == ".off") detail::check_off(file);
  Assimp::Importer importer;
  importer.SetIOHandler(new detail::GuardedIOSystem(file));
  detail::AssimpErrorLog errors;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // GenSmoothNormals only fills meshes that have no normals: the file's own normals are kept.
  const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_GenSmoothNormals | aiProcess_SortByPType;
  const aiScene* scene = importer.ReadFile(file.string(), flags);
  if (scene == nullptr || scene->mRootNode == nullptr ||
      (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || !errors.first_error().empty()) {
    std::string why = scene == nullptr ? importer.GetErrorString() : errors.first_error();
    throw Error(fmt::format("{}: cannot read the mesh: {}", file.string(),
                            why.empty() ? "assimp returned no scene" : why));
  }

  Mesh mesh;
  bool all_have_normals = true;
  collect(*scene, mesh, all_have_normals);
  if (!all_have_normals) mesh.normals.clear();
  return mesh;
}

}  // namespace

Mesh read_mesh(const std::filesystem::path& file) {
  require_regular_file(file);
  // Debian 12's assimp hangs or crashes on some malformed PLY files: those are read here.
  Mesh mesh = is_ply(file) ? detail::read_ply(file) : read_with_assimp(file);
  if (mesh.triangles.empty())
    throw Error(fmt::format("{}: the file holds no triangles", file.string()));
  if (mesh.normals.size() != mesh.positions.size()) compute_smooth_normals(mesh);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3& p = mesh.positions[i];
    if (!(std::abs(p.x) <= kMaxCoordinateMm && std::abs(p.y) <= kMaxCoordinateMm &&
          std::abs(p.z) <= kMaxCoordinateMm))
      throw Error(
          fmt::format("{}: vertex {} at ({:g}, {:g}, {:g}) is not a finite position within "
                      "{:g} mm of the origin",
                      file.string(), i, p.x, p.y, p.z, kMaxCoordinateMm));
  }
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const glm::uvec3& t = mesh.triangles[f];
    if (std::max({t.x, t.y, t.z}) >= mesh.positions.size())
      throw Error(fmt::format("{}: triangle {} uses vertex {}, but the file has {} vertices",
                              file.string(), f, std::max({t.x, t.y, t.z}), mesh.positions.size()));
  }
  return mesh;
}

}  // namespace imx
