// Movies from Python (intermix.write_movie, read_movie, orbit(..., path="x.mp4")): the same
// encoder as `intermix render --orbit` (src/movie/), written atomically.
#include <fmt/format.h>

#include "arguments.hpp"
#include "bindings.hpp"
#include "movie/movie_encoder.hpp"
#include "movie/movie_format.hpp"
#include "movie/movie_reader.hpp"
#include "movie/write_movie.hpp"

namespace imx::python {

void bind_movie(py::module_& m) {
  m.def(
      "_check_movie",
      [](const PathParameter& path, const IntParameter& width, const IntParameter& height,
         const RealParameter& fps) {
        const std::filesystem::path file = python::path(path, {"write_movie", "path"});
        const int w = static_cast<int>(int_in(width, {"write_movie", "width"}, 1, 1 << 16));
        const int h = static_cast<int>(int_in(height, {"write_movie", "height"}, 1, 1 << 16));
        const double rate = real_in(fps, {"write_movie", "fps"}, 1.0, 240.0);
        MovieEncoder::check(file.string(), movie_format_for(file), w, h, rate);
      },
      py::arg("path"), py::arg("width"), py::arg("height"), py::arg("fps"),
      "Raises ValueError for what write_movie would refuse before its first frame.");

  m.def(
      "_write_movie",
      [](const SceneValueParameter& images, const PathParameter& path, const RealParameter& fps) {
        const std::filesystem::path file = python::path(path, {"write_movie", "path"});
        MovieOptions options;
        options.fps = real_in(fps, {"write_movie", "fps"}, 1.0, 240.0);
        const py::sequence frames = images.cast<py::sequence>();
        if (frames.size() == 0)
          throw py::value_error("write_movie: images is empty; a movie needs at least one frame");
        const Image first = array_to_image(frames[0], "write_movie: images[0]");
        write_movie(
            file, first.width(), first.height(), static_cast<int>(frames.size()),
            [&](int k, const std::function<void(double)>&) {
              return k == 0 ? first
                            : array_to_image(frames[static_cast<size_t>(k)],
                                             fmt::format("write_movie: images[{}]", k));
            },
            options);
      },
      py::arg("images"), py::arg("path"), py::arg("fps"),
      "Writes a sequence of (H, W, 4) images as a movie (see intermix.write_movie).");

  m.def(
      "_read_movie",
      [](const PathParameter& path) {
        const std::filesystem::path file = python::path(path, {"read_movie", "path"});
        DecodedMovie movie;
        {
          py::gil_scoped_release release;
          movie = read_movie(file);
        }
        py::array_t<uint8_t> frames(std::vector<py::ssize_t>{
            static_cast<py::ssize_t>(movie.frames.size()), movie.height, movie.width, 3});
        uint8_t* out = frames.mutable_data();
        for (const std::vector<uint8_t>& f : movie.frames) out = std::copy(f.begin(), f.end(), out);
        py::dict d;
        d["frames"] = frames;
        d["fps"] = movie.fps;
        d["codec"] = movie.codec;
        d["pixel_format"] = movie.pixel_format;
        return d;
      },
      py::arg("path"), "A movie's frames as decoded (see intermix.read_movie).");

  py::list formats;
  for (const MovieFormat& f : movie_formats()) formats.append(f.extension);
  m.attr("_movie_extensions") = formats;
}

}  // namespace imx::python
