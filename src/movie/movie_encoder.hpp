// MovieEncoder: rendered images coded one by one into a movie on a seekable stream.
#pragma once
#include <memory>
#include <ostream>
#include <string>

#include "intermix/image.hpp"
#include "movie/movie_format.hpp"

namespace imx {

class MovieEncoder {
 public:
  // Starts a width x height movie of `format` at `fps` frames per second on `out` (which must
  // outlive the encoder and be seekable: the containers write sizes and indexes back). `what`
  // names the movie in errors. Throws imx::Error for a size the format cannot code, an encoder
  // this FFmpeg lacks, or a plugin that cannot be loaded.
  MovieEncoder(std::ostream& out, const MovieFormat& format, int width, int height, double fps,
               std::string what);
  ~MovieEncoder();
  // What the constructor checks before it writes anything (the plugin loaded, the encoder in
  // it, the size and rate): so that a movie's errors come before its frames are rendered.
  static void check(const std::string& what, const MovieFormat& format, int width, int height,
                    double fps);
  MovieEncoder(const MovieEncoder&) = delete;
  MovieEncoder& operator=(const MovieEncoder&) = delete;

  // Codes the next frame (movie_frame_rgb8 of it); its size must be the movie's.
  void add(const Image& image);
  // Flushes the encoder and writes the container's index; no frame may follow.
  void finish();
  int frames() const { return frames_; }

 private:
  struct Output;
  std::ostream& out_;
  std::string what_;
  int width_, height_;
  int frames_ = 0;
  bool finished_ = false;
  void* handle_ = nullptr;
  std::unique_ptr<Output> output_;
};

}  // namespace imx
