#include "movie/movie_reader.hpp"

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/input_file.hpp"
#include "movie/movie_plugin.hpp"

namespace imx {

DecodedMovie read_movie(const std::filesystem::path& file) {
  // The guarded open first: a missing file, a FIFO or a folder is named as every reader names
  // it (an OSError in Python), never in libavformat's words.
  open_input(file);
  const imx_movie_ffmpeg_calls& plugin = detail::movie_plugin();
  imx_movie_info info{};
  char error[512] = {};
  void* reader = plugin.reader_open(file.c_str(), &info, error, sizeof error);
  if (reader == nullptr) throw Error(fmt::format("{}: {}", file.string(), error));
  struct Close {
    const imx_movie_ffmpeg_calls& plugin;
    void* reader;
    ~Close() { plugin.reader_close(reader); }
  } close{plugin, reader};
  DecodedMovie movie;
  movie.width = info.width;
  movie.height = info.height;
  movie.fps = info.fps_den > 0 ? static_cast<double>(info.fps_num) / info.fps_den : 0.0;
  movie.codec = info.codec;
  movie.pixel_format = info.pixel_format;
  const size_t bytes = static_cast<size_t>(info.width) * info.height * 3;
  while (true) {
    std::vector<uint8_t> rgb(bytes);
    const int32_t got = plugin.reader_next(reader, rgb.data(), error, sizeof error);
    if (got < 0)
      throw Error(fmt::format("{}: frame {}: {}", file.string(), movie.frames.size(), error));
    if (got == 0) break;
    movie.frames.push_back(std::move(rgb));
  }
  return movie;
}

}  // namespace imx
