#include "io/registry/plugin_loader.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>

#include <fmt/format.h>

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
void* open_one(const PluginPlace& place, const std::string& path, std::string& why) {
  ::dlerror();
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | (place.global ? RTLD_GLOBAL : RTLD_LOCAL));
  if (handle == nullptr) {
    const char* e = ::dlerror();
    why = e != nullptr ? e : "dlopen failed";
    if (why.starts_with(path + ": ")) why.erase(0, path.size() + 2);  // named once is enough
    return nullptr;
  }
  using AbiFn = uint32_t (*)();
  auto abi = reinterpret_cast<AbiFn>(::dlsym(handle, place.abi_symbol));
  if (abi == nullptr) {
    why = fmt::format("not {} (no {})", place.what, place.abi_symbol);
  } else if (abi() != place.abi_version) {
    why = fmt::format("interface version {}, this build needs {}", abi(), place.abi_version);
  } else {
    return handle;  // never closed: what it returned may be in use until the process ends
  }
  ::dlclose(handle);
  return nullptr;
}

}  // namespace

std::vector<std::string> plugin_paths(const PluginPlace& place) {
  const char* env = std::getenv(place.env);
  if (env != nullptr && env[0] != '\0') return {env};
  std::vector<std::string> paths;
  auto add = [&](const std::string& p) {
    if (!p.empty() && std::find(paths.begin(), paths.end(), p) == paths.end()) paths.push_back(p);
  };
  const std::filesystem::path folder = own_folder();
  if (!folder.empty() && place.from_bindir[0] != '\0')
    add((folder / place.from_bindir).lexically_normal().string());
  add(place.installed);
  add(place.built);
  return paths;
}

void* open_plugin(const PluginPlace& place, std::string& tried) {
  tried.clear();
  for (const std::string& path : plugin_paths(place)) {
    std::string why;
    if (void* handle = open_one(place, path, why)) return handle;
    tried += fmt::format("{}{} ({})", tried.empty() ? "" : "; ", path, why);
  }
  if (tried.empty()) tried = "no path";
  return nullptr;
}

void* plugin_symbol(void* handle, const char* name) {
  return ::dlsym(handle, name);
}

}  // namespace imx::detail
