// imx::Error: the one exception type thrown at API boundaries; its message names the culprit.
#pragma once
#include <stdexcept>
#include <string>

namespace imx {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// A file that cannot be read or written: missing, not a regular file, no permission, a folder
// that cannot be listed, a failed write. `code` is the errno value when one is known (ENOENT,
// EISDIR, EACCES, ...), else 0. The Python package raises OSError for it, ValueError for any
// other imx::Error from reading (a file that is there but wrong).
class FileError : public Error {
 public:
  explicit FileError(const std::string& message, int code = 0) : Error(message), code_(code) {}
  int code() const { return code_; }

 private:
  int code_;
};

// An input that asks for more memory than the budget allows (check_memory), or more than the
// machine gives: the message names the input and the budget. The Python package raises
// MemoryError for it.
class OutOfMemory : public Error {
 public:
  explicit OutOfMemory(const std::string& message) : Error(message) {}
};

// A volume whose grid one process cannot hold at once (more than 2^31 voxels, or more bytes
// than half the memory budget): `intermix render` then renders it brick by brick.
class VolumeTooLarge : public OutOfMemory {
 public:
  explicit VolumeTooLarge(const std::string& message) : OutOfMemory(message) {}
};

// Thrown by render() when RenderOptions::cancel was set: not a failure, the frame is dropped.
class Cancelled : public Error {
 public:
  Cancelled() : Error("rendering cancelled") {}
};

}  // namespace imx
