#include "mesh_assimp/assimp_guard.hpp"

#include <algorithm>
#include <mutex>
#include <stdexcept>

#include <assimp/DefaultLogger.hpp>
#include <assimp/Logger.hpp>

namespace imx::detail {
namespace {

thread_local bool collecting = false;
thread_local std::string first_logged_error;

// assimp's one process-wide logger: keeps the first error of each collecting thread.
class ErrorCollector : public Assimp::Logger {
 public:
  bool attachStream(Assimp::LogStream*, unsigned) override { return false; }
  bool detachStream(Assimp::LogStream*, unsigned) override { return false; }

 private:
  void OnDebug(const char*) override {}
  void OnVerboseDebug(const char*) override {}
  void OnInfo(const char*) override {}
  void OnWarn(const char*) override {}
  void OnError(const char* message) override {
    if (collecting && first_logged_error.empty()) first_logged_error = message;
  }
};

bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec);
}

}  // namespace

bool GuardedIOSystem::Exists(const char* file) const {
  std::error_code ec;
  return std::filesystem::is_regular_file(file, ec);
}

Assimp::IOStream* GuardedIOSystem::Open(const char* file, const char* mode) {
  if (!same_file(file, mesh_)) {
    // assimp joins names in the mesh with the mesh's folder, relative to the working directory.
    char why[4096] = "";
    if (allow_(context_, std::filesystem::absolute(file).string().c_str(), why, sizeof why) != 0)
      throw std::runtime_error(why);
  }
  Assimp::IOStream* stream = DefaultIOSystem::Open(file, mode);
  if (stream != nullptr && pad_mesh_ && same_file(file, mesh_)) return new PaddedTextStream(stream);
  return stream;
}

PaddedTextStream::PaddedTextStream(Assimp::IOStream* file)
    : file_(file), file_size_(file->FileSize()) {}

PaddedTextStream::~PaddedTextStream() {
  delete file_;
}

size_t PaddedTextStream::Read(void* buffer, size_t size, size_t count) {
  if (size == 0 || count == 0) return 0;
  const size_t total = FileSize();
  count = std::min(count, (total - std::min(position_, total)) / size);
  auto* out = static_cast<char*>(buffer);
  size_t wanted = size * count, done = 0;
  if (position_ < file_size_) {
    const size_t from_file = std::min(wanted, file_size_ - position_);
    if (file_->Seek(position_, aiOrigin_SET) != aiReturn_SUCCESS ||
        file_->Read(out, 1, from_file) != from_file)
      return 0;
    done = from_file;
  }
  for (; done < wanted; ++done) out[done] = kPadding[position_ + done - file_size_];
  position_ += wanted;
  return count;
}

aiReturn PaddedTextStream::Seek(size_t offset, aiOrigin origin) {
  // Offsets back from here or the end come as negative numbers cast to size_t: the sums wrap.
  size_t to = offset;
  if (origin == aiOrigin_CUR) to = position_ + offset;
  if (origin == aiOrigin_END) to = FileSize() + offset;
  if (to > FileSize()) return aiReturn_FAILURE;
  position_ = to;
  return aiReturn_SUCCESS;
}

AssimpErrorLog::AssimpErrorLog() {
  static std::once_flag installed;
  std::call_once(installed, [] { Assimp::DefaultLogger::set(new ErrorCollector); });
  collecting = true;
  first_logged_error.clear();
}

AssimpErrorLog::~AssimpErrorLog() {
  collecting = false;
  std::string().swap(first_logged_error);  // no heap memory that only this thread's TLS holds
}

const std::string& AssimpErrorLog::first_error() const {
  return first_logged_error;
}

}  // namespace imx::detail
