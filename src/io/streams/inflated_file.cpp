#include "io/streams/inflated_file.hpp"

#include <system_error>

#include "intermix/error.hpp"
#include "io/streams/gzip.hpp"

namespace imx::detail {

InflatedFile::InflatedFile(const std::filesystem::path& file, const std::string& inner_name,
                           uint64_t max_bytes) {
  const std::string what = file.string();
  folder_ = make_inflate_folder(what);
  path_ = folder_ / inner_name;
  try {
    gunzip_file(file, path_, max_bytes, what, "more than the memory budget allows (--max-memory)");
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove_all(folder_, ec);
    throw;
  }
}

InflatedFile::~InflatedFile() {
  std::error_code ec;
  std::filesystem::remove_all(folder_, ec);
}

void rethrow_naming(const std::filesystem::path& temporary, const std::filesystem::path& file) {
  const auto renamed = [&](std::string message) {
    const std::string from = temporary.string(), to = file.string();
    for (size_t at = message.find(from); at != std::string::npos;
         at = message.find(from, at + to.size()))
      message.replace(at, from.size(), to);
    return message;
  };
  try {
    throw;
  } catch (const OutOfMemory& e) {
    throw OutOfMemory(renamed(e.what()));
  } catch (const FileError& e) {
    throw FileError(renamed(e.what()), e.code());
  } catch (const Error& e) {
    throw Error(renamed(e.what()));
  }
}

}  // namespace imx::detail
