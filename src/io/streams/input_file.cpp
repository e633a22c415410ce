#include "io/streams/input_file.hpp"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include "intermix/error.hpp"
#include "io/streams/input_identity.hpp"

namespace imx {
namespace {

std::string name_of(const std::filesystem::path& file, std::string_view what) {
  return what.empty() ? file.string() : std::string(what);
}

[[noreturn]] void refuse_kind(const std::string& name, unsigned mode) {
  throw FileError(fmt::format("{}: {}", name, not_regular_reason(mode)),
                  S_ISDIR(mode) ? EISDIR : 0);
}

// "NAME: no such file", or for a link whose target is not there, what it links to: the link
// itself is there to see.
std::string missing_file_message(const std::filesystem::path& file, const std::string& name,
                                 const char* missing) {
  std::error_code ec;
  if (std::filesystem::is_symlink(std::filesystem::symlink_status(file, ec))) {
    const std::filesystem::path target = std::filesystem::read_symlink(file, ec);
    if (!ec)
      return fmt::format("{}: a symbolic link to '{}', which is not there", name, target.string());
  }
  return fmt::format("{}: {}", name, missing);
}

// Why open(2) failed, in words: a path that exists but is no regular file (a socket gives
// ENXIO, a device may give EACCES) is said as what it is.
[[noreturn]] void refuse_open(const std::filesystem::path& file, const std::string& name, int err) {
  if (err == ELOOP)
    throw FileError(fmt::format("{}: symbolic link loop (too many levels of links)", name), ELOOP);
  if (err == ENOENT) throw FileError(missing_file_message(file, name, "no such file"), ENOENT);
  struct stat st {};
  if (::stat(file.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) refuse_kind(name, st.st_mode);
  throw FileError(fmt::format("{}: cannot open the file: {}", name, std::strerror(err)), err);
}

// The guarded open; `record`: note the file as an input (not for sniffing a neighbour's bytes).
InputFd open_checked(const std::filesystem::path& file, std::string_view what, bool record) {
  const std::string name = name_of(file, what);
  if (file.empty()) throw FileError(fmt::format("{}: no such file", name), ENOENT);
  // O_NONBLOCK: opening a FIFO with no writer, or a device, must not wait.
  int fd;
  do fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  while (fd < 0 && errno == EINTR);
  if (fd < 0) refuse_open(file, name, errno);
  InputFd guard(fd, 0);
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    throw FileError(fmt::format("{}: cannot look at the file: {}", name, std::strerror(errno)),
                    errno);
  if (!S_ISREG(st.st_mode)) refuse_kind(name, st.st_mode);
  const int flags = ::fcntl(fd, F_GETFL);  // reads of a regular file then block as usual
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  if (record) note_input(st, file);
  return InputFd(guard.release(), static_cast<uint64_t>(st.st_size));
}

}  // namespace

std::string not_regular_reason(unsigned mode) {
  if (S_ISDIR(mode)) return "is a directory, not a file";
  return fmt::format("is {}, not a regular file", kind_name(mode));
}

const char* kind_name(unsigned mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISREG(mode)) return "a file";
  return "not a file or folder";
}

InputFd& InputFd::operator=(InputFd&& other) noexcept {
  if (this != &other) {
    reset();
    fd_ = other.fd_;
    size_ = other.size_;
    other.fd_ = -1;
  }
  return *this;
}

int InputFd::release() {
  const int fd = fd_;
  fd_ = -1;
  return fd;
}

void InputFd::reset() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

InputFd open_input(const std::filesystem::path& file, std::string_view what) {
  return open_checked(file, what, true);
}

InputFd open_input_unrecorded(const std::filesystem::path& file, std::string_view what) {
  return open_checked(file, what, false);
}

std::filesystem::path path_of_open(const InputFd& fd, const std::filesystem::path& file) {
  std::filesystem::path proc = fmt::format("/proc/self/fd/{}", fd.get());
  struct stat a {
  }, b{};
  if (fd.get() >= 0 && ::stat(proc.c_str(), &a) == 0 && ::fstat(fd.get(), &b) == 0 &&
      a.st_dev == b.st_dev && a.st_ino == b.st_ino)
    return proc;
  return file;
}

std::ifstream open_input_stream(const std::filesystem::path& file, std::string_view what,
                                std::ios::openmode mode) {
  const InputFd fd = open_input(file, what);
  std::ifstream in(path_of_open(fd, file), mode | std::ios::in);
  if (!in)
    throw FileError(
        fmt::format("{}: cannot open the file: {}", name_of(file, what), std::strerror(errno)),
        errno);
  return in;
}

std::ifstream try_open_input_stream(const std::filesystem::path& file) {
  try {
    const InputFd fd = open_checked(file, {}, false);
    return std::ifstream(path_of_open(fd, file), std::ios::binary);
  } catch (const Error&) {
    return std::ifstream();
  }
}

void require_input_folder(const std::filesystem::path& folder, std::string_view what) {
  const std::string name = name_of(folder, what);
  struct stat st {};
  if (::stat(folder.c_str(), &st) != 0) {
    const int err = errno;
    if (err == ELOOP)
      throw FileError(fmt::format("{}: symbolic link loop (too many levels of links)", name),
                      ELOOP);
    if (err == ENOENT)
      throw FileError(missing_file_message(folder, name, "no such file or folder"), ENOENT);
    throw FileError(fmt::format("{}: cannot look at the folder: {}", name, std::strerror(err)),
                    err);
  }
  if (S_ISDIR(st.st_mode)) return;
  throw FileError(fmt::format("{}: is {}, not a folder", name, kind_name(st.st_mode)), ENOTDIR);
}

}  // namespace imx
