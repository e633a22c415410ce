// write_movie: a movie of rendered frames written atomically, with progress.
#pragma once
#include <filesystem>
#include <functional>

#include "intermix/image.hpp"

namespace imx {

struct MovieOptions {
  double fps = 24.0;
  // Called with the finished fraction in [0, 1] (frames rendered and coded so far).
  std::function<void(double)> progress;
};

// Renders frame k = 0 .. frames - 1 with `frame(k, progress_within_frame)`, each width x height,
// and codes it into `file`, whose extension chooses the format (movie_format.hpp). What can be
// checked before rendering is (the name, the size, the encoder, an output over an input). The movie
// is written to a temporary file beside `file` and renamed into place only when every frame is in
// (write_file_atomically): on any error nothing is left, an existing file stays as it was, and
// a `file` that names an input is refused before the first frame is rendered.
void write_movie(const std::filesystem::path& file, int width, int height, int frames,
                 const std::function<Image(int, const std::function<void(double)>&)>& frame,
                 const MovieOptions& options = {});

}  // namespace imx
