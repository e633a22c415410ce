// What the mesh plugin puts around an assimp import: files assimp opens by itself (an OBJ's
// mtllib, glTF buffers) are held to the rules for data files, and errors assimp only logs (and
// then works around, such as clamping a face index) fail the import.
#pragma once
#include <filesystem>
#include <string>

#include <assimp/DefaultIOSystem.h>

#include "mesh_assimp/mesh_assimp_abi.h"

namespace imx::detail {

// The importer's file system: the mesh file itself, and any other file only when the caller's
// `allow` accepts it (imx_io's resolve_data_file: a regular file inside the mesh's folder unless
// --allow-external-data). A refusal is thrown as std::runtime_error, which assimp turns into its
// error.
class GuardedIOSystem : public Assimp::DefaultIOSystem {
 public:
  GuardedIOSystem(std::filesystem::path mesh, imx_mesh_assimp_allow_fn allow, void* context)
      : mesh_(std::move(mesh)), allow_(allow), context_(context) {}
  bool Exists(const char* file) const override;
  Assimp::IOStream* Open(const char* file, const char* mode = "rb") override;

 private:
  std::filesystem::path mesh_;
  imx_mesh_assimp_allow_fn allow_;
  void* context_;
};

// Collects what assimp logs as errors on this thread while it lives.
class AssimpErrorLog {
 public:
  AssimpErrorLog();
  ~AssimpErrorLog();
  AssimpErrorLog(const AssimpErrorLog&) = delete;
  AssimpErrorLog& operator=(const AssimpErrorLog&) = delete;
  // The first error logged, empty when none.
  const std::string& first_error() const;
};

}  // namespace imx::detail
