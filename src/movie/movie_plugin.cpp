#include "movie/movie_plugin.hpp"

#include <mutex>
#include <string>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/registry/plugin_loader.hpp"

// CMake defines these on this file's command line only (CMakeLists.txt), so that no other
// compile names the build or install folder.
#ifndef IMX_MOVIE_PLUGIN_BUILT
#define IMX_MOVIE_PLUGIN_BUILT ""
#endif
#ifndef IMX_MOVIE_PLUGIN_INSTALLED
#define IMX_MOVIE_PLUGIN_INSTALLED ""
#endif
#ifndef IMX_MOVIE_PLUGIN_FROM_BINDIR
#define IMX_MOVIE_PLUGIN_FROM_BINDIR ""
#endif

namespace imx::detail {

namespace {

constexpr PluginPlace kPlace{"an intermix movie plugin",   "IMX_MOVIE_PLUGIN",
                             IMX_MOVIE_PLUGIN_FROM_BINDIR, IMX_MOVIE_PLUGIN_INSTALLED,
                             IMX_MOVIE_PLUGIN_BUILT,       IMX_MOVIE_FFMPEG_ABI_SYMBOL,
                             IMX_MOVIE_FFMPEG_ABI_VERSION};

}  // namespace

const imx_movie_ffmpeg_calls& movie_plugin() {
  // A failure is not kept: a later movie tries again (IMX_MOVIE_PLUGIN may have been set since).
  static std::mutex mutex;
  static const imx_movie_ffmpeg_calls* loaded = nullptr;
  std::lock_guard lock(mutex);
  if (loaded != nullptr) return *loaded;
  std::string tried;
  if (void* handle = open_plugin(kPlace, tried)) {
    auto calls = reinterpret_cast<imx_movie_ffmpeg_calls_fn>(
        plugin_symbol(handle, IMX_MOVIE_FFMPEG_CALLS_SYMBOL));
    if (calls != nullptr && calls() != nullptr) return *(loaded = calls());
    tried = "a plugin without " IMX_MOVIE_FFMPEG_CALLS_SYMBOL;
  }
  throw Error(
      fmt::format("movies need the movie plugin (FFmpeg), which cannot be loaded (tried: {}); set "
                  "IMX_MOVIE_PLUGIN to the path of libimx_movie_ffmpeg.so",
                  tried));
}

}  // namespace imx::detail
