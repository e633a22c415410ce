// What intermix puts around an assimp import: files assimp opens by itself (an OBJ's mtllib,
// glTF buffers) are held to the rules for data files, and errors assimp only logs (and then
// works around, such as clamping a face index) fail the import.
#pragma once
#include <filesystem>
#include <string>

#include <assimp/DefaultIOSystem.h>

namespace imx::detail {

// The importer's file system: the mesh file itself, and any other file only when
// resolve_data_file() accepts it (a regular file inside the mesh's folder unless
// --allow-external-data). A refusal is thrown as imx::Error, which assimp turns into its error.
class GuardedIOSystem : public Assimp::DefaultIOSystem {
 public:
  explicit GuardedIOSystem(std::filesystem::path mesh) : mesh_(std::move(mesh)) {}
  bool Exists(const char* file) const override;
  Assimp::IOStream* Open(const char* file, const char* mode = "rb") override;

 private:
  std::filesystem::path mesh_;
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
