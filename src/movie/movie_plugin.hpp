// The movie plugin (libimx_movie_ffmpeg.so: FFmpeg's libraries), opened on the first movie.
#pragma once
#include "movie_ffmpeg/movie_ffmpeg_abi.h"

namespace imx::detail {

// The plugin's calls, loaded once per process; throws imx::Error naming the paths tried (and
// IMX_MOVIE_PLUGIN, which overrides them) when it cannot be loaded.
const imx_movie_ffmpeg_calls& movie_plugin();

}  // namespace imx::detail
