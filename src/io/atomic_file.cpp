#include "io/atomic_file.hpp"
#include "io/regular_file.hpp"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <system_error>

#include <fmt/format.h>
#include <unistd.h>

#include "core/hash.hpp"
#include "intermix/error.hpp"

namespace imx {

namespace {

// Creates a new, empty, uniquely named file beside `file` and returns its path. "wx" is
// exclusive creation, so two writers never share a temporary, and the umask applies.
std::filesystem::path create_temporary(const std::filesystem::path& file) {
  static std::atomic<uint32_t> counter{0};
  uint32_t seed =
      hash_u32(static_cast<uint32_t>(::getpid())) ^
      static_cast<uint32_t>(std::chrono::steady_clock::now().time_since_epoch().count());
  int last_errno = 0;
  for (int attempt = 0; attempt < 64; ++attempt) {
    uint32_t tag = hash_u32(seed ^ hash_u32(counter.fetch_add(1)));
    std::filesystem::path tmp = file;
    tmp += fmt::format(".tmp-{:08x}", tag);
    if (std::FILE* f = std::fopen(tmp.c_str(), "wx")) {
      std::fclose(f);
      return tmp;
    }
    last_errno = errno;
    if (last_errno != EEXIST) break;
  }
  std::filesystem::path folder = file.parent_path().empty() ? "." : file.parent_path();
  throw Error(fmt::format("{}: cannot create a file in folder '{}': {}", file.string(),
                          folder.string(), std::strerror(last_errno)));
}

void remove_quietly(const std::filesystem::path& p) {
  std::error_code ec;
  std::filesystem::remove(p, ec);
}

}  // namespace

void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(std::ostream&)>& write) {
  require_regular_or_new_file(file);  // renaming over a device or FIFO would replace it
  std::filesystem::path tmp = create_temporary(file);
  try {
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out)
        throw Error(fmt::format("{}: cannot open '{}' for writing", file.string(), tmp.string()));
      write(out);
      out.flush();
      if (!out) throw Error(fmt::format("{}: writing failed (disk full?)", file.string()));
      out.close();
      if (out.fail()) throw Error(fmt::format("{}: closing failed (disk full?)", file.string()));
    }
    std::error_code ec;
    std::filesystem::rename(tmp, file, ec);
    if (ec)
      throw Error(fmt::format("{}: cannot rename the temporary file into place: {}", file.string(),
                              ec.message()));
  } catch (...) {
    remove_quietly(tmp);
    throw;
  }
}

}  // namespace imx
