#include "mesh_assimp/assimp_guard.hpp"

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
  return DefaultIOSystem::Open(file, mode);
}

AssimpErrorLog::AssimpErrorLog() {
  static std::once_flag installed;
  std::call_once(installed, [] { Assimp::DefaultLogger::set(new ErrorCollector); });
  collecting = true;
  first_logged_error.clear();
}

AssimpErrorLog::~AssimpErrorLog() {
  collecting = false;
}

const std::string& AssimpErrorLog::first_error() const {
  return first_logged_error;
}

}  // namespace imx::detail
