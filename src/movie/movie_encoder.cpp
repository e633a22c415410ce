#include "movie/movie_encoder.hpp"

#include <algorithm>
#include <cstdio>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "movie/movie_frame.hpp"
#include "movie/movie_plugin.hpp"

namespace imx {

// The plugin's view of `out_`: writes, seeks and the size written so far (the muxers ask).
struct MovieEncoder::Output {
  std::ostream* out;
  int64_t size = 0;
  imx_movie_output calls{};

  static int32_t write(void* context, const uint8_t* data, int32_t size) {
    auto* self = static_cast<Output*>(context);
    self->out->write(reinterpret_cast<const char*>(data), size);
    if (!*self->out) return 1;
    self->size = std::max<int64_t>(self->size, static_cast<int64_t>(self->out->tellp()));
    return 0;
  }

  static int64_t seek(void* context, int64_t offset, int32_t whence) {
    auto* self = static_cast<Output*>(context);
    if (whence == IMX_MOVIE_SEEK_SIZE) return self->size;
    int64_t target = offset;
    if (whence == SEEK_CUR) target += static_cast<int64_t>(self->out->tellp());
    if (whence == SEEK_END) target += self->size;
    if (target < 0) return -1;
    self->out->seekp(target);
    return *self->out ? target : -1;
  }
};

namespace {

// Frames per second as the fraction libavformat keeps: whole numbers exactly, others to 1/1000.
std::pair<int, int> fps_fraction(double fps) {
  if (fps == static_cast<int>(fps)) return {static_cast<int>(fps), 1};
  return {static_cast<int>(fps * 1000.0 + 0.5), 1000};
}

}  // namespace

void MovieEncoder::check(const std::string& what, const MovieFormat& format, int width, int height,
                         double fps) {
  check_movie_size(what, format, width, height);
  if (!(fps >= 1.0 && fps <= 240.0))
    throw Error(fmt::format("{}: {} frames per second is not in [1, 240]", what, fps));
  const imx_movie_ffmpeg_calls& plugin = detail::movie_plugin();
  if (plugin.has_encoder(format.encoder.c_str()) == 0)
    throw Error(fmt::format(
        "{}: {} needs FFmpeg's {} encoder, which this FFmpeg ({}) lacks; choose another format "
        "(.mp4, .webm, .mkv) or install Debian's libavcodec, which has it",
        what, format.codec, format.encoder, plugin.versions()));
}

MovieEncoder::MovieEncoder(std::ostream& out, const MovieFormat& format, int width, int height,
                           double fps, std::string what)
    : out_(out), what_(std::move(what)), width_(width), height_(height) {
  check(what_, format, width, height, fps);
  const imx_movie_ffmpeg_calls& plugin = detail::movie_plugin();
  output_ = std::make_unique<Output>(Output{&out_});
  output_->calls = imx_movie_output{output_.get(), &Output::write, &Output::seek};
  const auto [num, den] = fps_fraction(fps);
  const imx_movie_settings settings{format.container.c_str(),
                                    format.encoder.c_str(),
                                    format.pixel_format.c_str(),
                                    format.options.c_str(),
                                    width,
                                    height,
                                    num,
                                    den};
  char error[512] = {};
  handle_ = plugin.encoder_open(&settings, &output_->calls, error, sizeof error);
  if (handle_ == nullptr) throw Error(fmt::format("{}: {}", what_, error));
}

MovieEncoder::~MovieEncoder() {
  if (handle_ != nullptr) detail::movie_plugin().encoder_close(handle_);
}

void MovieEncoder::add(const Image& image) {
  if (finished_) throw Error(fmt::format("{}: a frame after the movie was finished", what_));
  if (image.width() != width_ || image.height() != height_)
    throw Error(fmt::format("{}: frame {} is {}x{}, the movie {}x{}", what_, frames_, image.width(),
                            image.height(), width_, height_));
  const std::vector<uint8_t> rgb = movie_frame_rgb8(image);
  char error[512] = {};
  if (detail::movie_plugin().encoder_add(handle_, rgb.data(), error, sizeof error) != 0)
    throw Error(fmt::format("{}: frame {}: {}", what_, frames_, error));
  ++frames_;
}

void MovieEncoder::finish() {
  if (finished_) return;
  if (frames_ == 0) throw Error(fmt::format("{}: a movie needs at least one frame", what_));
  char error[512] = {};
  if (detail::movie_plugin().encoder_finish(handle_, error, sizeof error) != 0)
    throw Error(fmt::format("{}: {}", what_, error));
  finished_ = true;
}

}  // namespace imx
