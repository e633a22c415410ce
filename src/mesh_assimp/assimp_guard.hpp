// What the mesh plugin puts around an assimp import: files assimp opens by itself (an OBJ's
// mtllib, glTF buffers) are held to the rules for data files, and errors assimp only logs (and
// then works around, such as clamping a face index) fail the import.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>

#include <assimp/DefaultIOSystem.h>
#include <assimp/IOStream.hpp>

#include "mesh_assimp/mesh_assimp_abi.h"

namespace imx::detail {

// The importer's file system: the mesh file itself, and any other file only when the caller's
// `allow` accepts it (imx_io's resolve_data_file: a regular file inside the mesh's folder unless
// --allow-external-data). A refusal is thrown as std::runtime_error, which assimp turns into its
// error.
class GuardedIOSystem : public Assimp::DefaultIOSystem {
 public:
  // `pad_mesh`: the mesh file is read with two newlines after its end (see PaddedTextStream).
  GuardedIOSystem(std::filesystem::path mesh, bool pad_mesh, imx_mesh_assimp_allow_fn allow,
                  void* context)
      : mesh_(std::move(mesh)), pad_mesh_(pad_mesh), allow_(allow), context_(context) {}
  bool Exists(const char* file) const override;
  Assimp::IOStream* Open(const char* file, const char* mode = "rb") override;

 private:
  std::filesystem::path mesh_;
  bool pad_mesh_;
  imx_mesh_assimp_allow_fn allow_;
  void* context_;
};

// A file followed by two newlines. assimp's OBJ reader copies each line into a buffer as long as
// the file and ends it with a newline only, then reads numbers with strtol: a one-line file fills
// that buffer to its last byte, and a trailing line continuation ("\\" then CR, no LF) sends it
// looking for a newline past the data. Two blank lines at the end leave a zero byte after every
// line and a newline after every continuation, and mean nothing to OBJ.
class PaddedTextStream : public Assimp::IOStream {
 public:
  explicit PaddedTextStream(Assimp::IOStream* file);
  ~PaddedTextStream() override;
  size_t Read(void* buffer, size_t size, size_t count) override;
  size_t Write(const void*, size_t, size_t) override { return 0; }
  aiReturn Seek(size_t offset, aiOrigin origin) override;
  size_t Tell() const override { return position_; }
  size_t FileSize() const override { return file_size_ + kPadding.size(); }
  void Flush() override {}

 private:
  static constexpr std::string_view kPadding = "\n\n";
  Assimp::IOStream* file_;
  size_t file_size_;
  size_t position_ = 0;
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
