// A whole input file mapped read-only: tractograms of a gigabyte are read in place, once, without
// a heap copy of their bytes.
#pragma once
#include <cstddef>
#include <filesystem>
#include <string_view>

namespace imx::detail {

class MappedFile {
 public:
  // Throws imx::FileError naming `file` when it is not a regular file or cannot be mapped.
  explicit MappedFile(const std::filesystem::path& file);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  std::string_view bytes() const { return {data_, size_}; }

 private:
  const char* data_ = nullptr;
  size_t size_ = 0;
};

}  // namespace imx::detail
