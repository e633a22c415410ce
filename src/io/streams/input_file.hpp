// The one guarded open of every input file: opened without blocking, then checked on the open
// descriptor to be a regular file, so a FIFO, a device, a socket, a folder or a symbolic link
// loop is refused by name before the first read and never blocks the reader (issue 48).
#pragma once
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace imx {

// An open, read-only descriptor of a regular file, closed when destroyed.
class InputFd {
 public:
  InputFd() = default;
  InputFd(int fd, uint64_t size) : fd_(fd), size_(size) {}
  ~InputFd() { reset(); }
  InputFd(InputFd&& other) noexcept : fd_(other.fd_), size_(other.size_) { other.fd_ = -1; }
  InputFd& operator=(InputFd&& other) noexcept;
  InputFd(const InputFd&) = delete;
  InputFd& operator=(const InputFd&) = delete;

  int get() const { return fd_; }
  uint64_t size() const { return size_; }  // the size fstat gave when it was opened
  // The descriptor, now the caller's to close (for fdopen or a library that takes it over).
  int release();
  void reset();

 private:
  int fd_ = -1;
  uint64_t size_ = 0;
};

// Opens `file` for reading: O_NONBLOCK | O_NOCTTY | O_CLOEXEC, then fstat on the descriptor must
// say a regular file (O_NONBLOCK is then cleared). Throws imx::FileError naming `what` (else the
// path) and what the file is: "no such file", "is a FIFO (named pipe), not a regular file",
// "is a character device, ...", "is a directory, not a file", "symbolic link loop ...",
// "cannot open the file: <reason>". The file is recorded as an input of this process
// (io/streams/input_identity.hpp), so that no output replaces it.
InputFd open_input(const std::filesystem::path& file, std::string_view what = {});

// open_input without recording the file as an input: for a folder's files, which are sniffed,
// but whose open failure (a permission) must be said as such. Same errors.
InputFd open_input_unrecorded(const std::filesystem::path& file, std::string_view what = {});

// open_input, as a std::ifstream on the same open file (through /proc/self/fd, so the stream
// cannot reach another file than the one checked). Same errors.
std::ifstream open_input_stream(const std::filesystem::path& file, std::string_view what = {},
                                std::ios::openmode mode = std::ios::binary);

// For sniffing a file's first bytes: open_input_stream, or a stream that is not open (every read
// fails) when the file cannot be opened or is no regular file; never blocks. A file only sniffed
// (a folder's other files) is not recorded as an input.
std::ifstream try_open_input_stream(const std::filesystem::path& file);

// A path that reads the file `fd` has open (/proc/self/fd/N), for a library that opens by name
// (HDF5, libtiff, Assimp, GDCM): it then opens the checked file and no other. `file` itself
// when /proc is not mounted.
std::filesystem::path path_of_open(const InputFd& fd, const std::filesystem::path& file);

// For formats that are folders (OME-Zarr, DICOM series): throws imx::FileError naming `what`
// unless `folder` is a folder once links are resolved: "no such file or folder", "symbolic link
// loop", "is a FIFO ... not a folder".
void require_input_folder(const std::filesystem::path& folder, std::string_view what = {});

// "is a FIFO (named pipe), not a regular file" and the like, for a file of mode `st_mode`.
std::string not_regular_reason(unsigned st_mode);
// "a FIFO (named pipe)", "a character device", "a directory", ...: what a file of `st_mode` is.
const char* kind_name(unsigned st_mode);

}  // namespace imx
