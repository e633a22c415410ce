// Plugins intermix opens with dlopen on first use (the DICOM codecs, assimp's mesh importers,
// MPI), so that the libraries behind them are not loaded, nor relocated, at every start-up.
// Each plugin has a plain C interface whose version function must return the version this
// build was compiled against.
#pragma once
#include <string>
#include <vector>

namespace imx::detail {

// Where one plugin is looked for, as CMake gave the paths to the caller's compile.
struct PluginPlace {
  const char* what;         // "the DICOM codec plugin", for messages
  const char* env;          // an environment variable that, when set, is the only path tried
  const char* from_bindir;  // relative to the program's (or module's) folder, as installed
  const char* installed;    // the install prefix's path
  const char* built;        // the build tree's path
  const char* abi_symbol;   // a uint32_t (*)(void) returning `abi_version`
  unsigned abi_version;
  bool global = false;  // RTLD_GLOBAL: the plugin's libraries load modules of their own (MPI)
};

// The paths tried, in order: $env alone when it is set and not empty; else beside the program
// or module as installed, the install prefix's path, and the build tree's.
std::vector<std::string> plugin_paths(const PluginPlace& place);

// The handle of the first path that gives a plugin of this build's interface version (never
// closed). Else null, with `tried` set to "PATH (why); PATH (why)" for every path tried.
void* open_plugin(const PluginPlace& place, std::string& tried);

// A symbol of an open plugin, null when it has none.
void* plugin_symbol(void* handle, const char* name);

}  // namespace imx::detail
