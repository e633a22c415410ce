#include "io/dicom/dicom_codec_plugin.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <mutex>

#include <fmt/format.h>

#include "intermix/error.hpp"

// CMake defines these on this file's command line only (CMakeLists.txt), so that no other
// compile names the build or install folder.
#ifndef IMX_DICOM_CODEC_BUILT
#define IMX_DICOM_CODEC_BUILT ""
#endif
#ifndef IMX_DICOM_CODEC_INSTALLED
#define IMX_DICOM_CODEC_INSTALLED ""
#endif
#ifndef IMX_DICOM_CODEC_FROM_BINDIR
#define IMX_DICOM_CODEC_FROM_BINDIR ""
#endif

namespace imx::detail {

namespace {

// The folder of the program or shared module this code was linked into (the static imx_io is in
// the intermix program, a test, or the Python module).
std::filesystem::path own_folder() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&own_folder), &info) == 0 || info.dli_fname == nullptr ||
      info.dli_fname[0] == '\0')
    return {};
  std::error_code ec;
  std::filesystem::path self = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::filesystem::path() : self.parent_path();
}

// One path's plugin, or why not.
imx_dicom_codec_decode_fn open_plugin(const std::string& path, std::string& why) {
  ::dlerror();
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* e = ::dlerror();
    why = e != nullptr ? e : "dlopen failed";
    if (why.starts_with(path + ": ")) why.erase(0, path.size() + 2);  // named once is enough
    return nullptr;
  }
  auto abi = reinterpret_cast<imx_dicom_codec_abi_fn>(::dlsym(handle, IMX_DICOM_CODEC_ABI_SYMBOL));
  auto decode =
      reinterpret_cast<imx_dicom_codec_decode_fn>(::dlsym(handle, IMX_DICOM_CODEC_DECODE_SYMBOL));
  if (abi == nullptr || decode == nullptr) {
    why = "not an intermix DICOM codec plugin (no " IMX_DICOM_CODEC_DECODE_SYMBOL ")";
  } else if (abi() != IMX_DICOM_CODEC_ABI_VERSION) {
    why = fmt::format("interface version {}, this build needs {}", abi(),
                      IMX_DICOM_CODEC_ABI_VERSION);
  } else {
    return decode;  // never closed: decoders run until the process ends
  }
  ::dlclose(handle);
  return nullptr;
}

}  // namespace

std::vector<std::string> dicom_codec_paths() {
  const char* env = std::getenv("IMX_DICOM_CODEC");
  if (env != nullptr && env[0] != '\0') return {env};
  std::vector<std::string> paths;
  auto add = [&](const std::string& p) {
    if (!p.empty() && std::find(paths.begin(), paths.end(), p) == paths.end()) paths.push_back(p);
  };
  const std::filesystem::path folder = own_folder();
  if (!folder.empty() && IMX_DICOM_CODEC_FROM_BINDIR[0] != '\0')
    add((folder / IMX_DICOM_CODEC_FROM_BINDIR).lexically_normal().string());
  add(IMX_DICOM_CODEC_INSTALLED);
  add(IMX_DICOM_CODEC_BUILT);
  return paths;
}

imx_dicom_codec_decode_fn dicom_codec(const std::string& file) {
  // A failure is not kept: a later file tries again (IMX_DICOM_CODEC may have been set since).
  static std::mutex mutex;
  static imx_dicom_codec_decode_fn loaded = nullptr;
  std::lock_guard lock(mutex);
  if (loaded != nullptr) return loaded;
  std::string tried;
  for (const std::string& path : dicom_codec_paths()) {
    std::string why;
    loaded = open_plugin(path, why);
    if (loaded != nullptr) return loaded;
    tried += fmt::format("{}{} ({})", tried.empty() ? "" : "; ", path, why);
  }
  throw Error(fmt::format(
      "{}: its pixel data needs the DICOM codec plugin, which cannot be loaded (tried: {}); set "
      "IMX_DICOM_CODEC to the path of libimx_dicom_codec.so",
      file, tried.empty() ? "no path" : tried));
}

}  // namespace imx::detail
