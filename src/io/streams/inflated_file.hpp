// The one bounded inflation of a gzip file that readers take only by name (a row's .gz,
// x.obj.gz): inflated into a private temporary folder with gunzip_file's bound, errors naming
// the user's file. Every container reader inflates through here or gzip.hpp; none writes its own.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>

#include "intermix/error.hpp"

namespace imx::detail {

// Inflates `file` (gzip) to a temporary file beside the system's temporary folder, named as
// `inner_name` (the file name without .gz), at most `max_bytes`; the file is removed when the
// returned object goes. Errors name `file`.
class InflatedFile {
 public:
  InflatedFile(const std::filesystem::path& file, const std::string& inner_name,
               uint64_t max_bytes);
  ~InflatedFile();
  InflatedFile(const InflatedFile&) = delete;
  InflatedFile& operator=(const InflatedFile&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path folder_, path_;
};

// Runs `read(path)` on the inflated copy of a .gz file, its errors naming `file` instead of the
// temporary copy.
template <class Read>
auto read_inflated(const std::filesystem::path& file, uint64_t max_bytes, Read&& read);

// Rethrows the imx::Error being handled, of the same type, with `temporary` replaced by `file`
// in its message.
[[noreturn]] void rethrow_naming(const std::filesystem::path& temporary,
                                 const std::filesystem::path& file);

template <class Read>
auto read_inflated(const std::filesystem::path& file, uint64_t max_bytes, Read&& read) {
  std::string inner = file.filename().string();
  inner.resize(inner.size() - 3);  // without ".gz"
  const InflatedFile copy(file, inner, max_bytes);
  try {
    return std::forward<Read>(read)(copy.path());
  } catch (const Error&) {
    rethrow_naming(copy.path(), file);
  }
}

}  // namespace imx::detail
