#include "movie/write_movie.hpp"

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/atomic_file.hpp"
#include "movie/movie_encoder.hpp"
#include "movie/movie_format.hpp"

namespace imx {

void write_movie(const std::filesystem::path& file, int width, int height, int frames,
                 const std::function<Image(int, const std::function<void(double)>&)>& frame,
                 const MovieOptions& options) {
  const MovieFormat& format = movie_format_for(file);
  if (frames < 1) throw Error(fmt::format("{}: a movie needs at least one frame", file.string()));
  MovieEncoder::check(file.string(), format, width, height, options.fps);
  const auto report = [&](double done) {
    if (options.progress) options.progress(done / frames);
  };
  write_file_atomically(file, [&](std::ostream& out) {
    MovieEncoder encoder(out, format, width, height, options.fps, file.string());
    for (int k = 0; k < frames; ++k) {
      encoder.add(frame(k, [&](double f) { report(k + f); }));
      report(k + 1);
    }
    encoder.finish();
  });
}

}  // namespace imx
