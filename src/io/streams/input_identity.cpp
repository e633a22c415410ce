#include "io/streams/input_identity.hpp"

#include <cerrno>
#include <map>
#include <mutex>
#include <tuple>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx {
namespace {

// The modification time is part of the identity so that an input deleted during a long session
// (a test program, the viewer) whose inode the file system reuses for a new file is not it.
using Identity = std::tuple<dev_t, ino_t, time_t, long>;

Identity identity_of(const struct stat& st) {
  return {st.st_dev, st.st_ino, st.st_mtim.tv_sec, st.st_mtim.tv_nsec};
}

struct Inputs {
  std::mutex mutex;
  std::map<Identity, std::filesystem::path> files;
};

Inputs& inputs() {
  static Inputs* all = new Inputs;  // never destroyed: readers may run during static destruction
  return *all;
}

}  // namespace

void note_input(const struct stat& st, const std::filesystem::path& file) {
  Inputs& all = inputs();
  const std::lock_guard lock(all.mutex);
  all.files.try_emplace(identity_of(st), file);
}

std::optional<std::filesystem::path> input_named_by(const std::filesystem::path& output) {
  struct stat st {};
  if (::stat(output.c_str(), &st) != 0) return std::nullopt;  // a new file replaces nothing
  Inputs& all = inputs();
  const std::lock_guard lock(all.mutex);
  const auto it = all.files.find(identity_of(st));
  if (it == all.files.end()) return std::nullopt;
  return it->second;
}

void refuse_output_over_input(const std::filesystem::path& output) {
  if (const auto input = input_named_by(output))
    throw FileError(fmt::format("{}: is an input of this command ({}); choose another output",
                                output.string(), input->string()),
                    EEXIST);
}

}  // namespace imx
