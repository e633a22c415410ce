// The movie plugin (movie_ffmpeg_abi.h): RGB frames encoded with libavcodec, muxed with
// libavformat into the caller's output, and movies decoded back to RGB, colours converted with
// libswscale (BT.709 limited range for YUV, tagged so that players decode what was coded).
#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <memory>
#include <new>
#include <string>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/dict.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include "movie_ffmpeg/movie_ffmpeg_abi.h"

namespace {

// FFmpeg's own messages are not printed: the last error it logged in this thread is kept and
// ends the reason a call gives (FFmpeg's lines would otherwise interleave with the progress bar).
thread_local std::string t_last_log;

void keep_errors(void* context, int level, const char* format, va_list args) {
  if (level > AV_LOG_ERROR) return;
  char line[512];
  int prefix = 1;
  av_log_format_line2(context, level, format, args, line, sizeof line, &prefix);
  std::string text = line;
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  if (!text.empty()) t_last_log = text;
}

void quiet_ffmpeg() {
  static const bool once = [] {
    av_log_set_callback(keep_errors);
    return true;
  }();
  (void)once;
  t_last_log.clear();
}

void say(char* error, size_t size, const std::string& text) {
  const std::string full = t_last_log.empty() ? text : text + " (" + t_last_log + ")";
  if (size > 0) std::snprintf(error, size, "%s", full.c_str());
}

std::string av_message(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof text);
  return text;
}

// ---- encoding --------------------------------------------------------------------------------

int write_packet(void* opaque, uint8_t* data, int size) {
  const auto* out = static_cast<const imx_movie_output*>(opaque);
  return out->write(out->context, data, size) == 0 ? size : AVERROR(EIO);
}

int64_t seek_output(void* opaque, int64_t offset, int whence) {
  const auto* out = static_cast<const imx_movie_output*>(opaque);
  whence &= ~AVSEEK_FORCE;
  if (whence == AVSEEK_SIZE) whence = IMX_MOVIE_SEEK_SIZE;
  const int64_t at = out->seek(out->context, offset, whence);
  return at < 0 ? AVERROR(EIO) : at;
}

struct Encoder {
  imx_movie_output output{};
  AVFormatContext* format = nullptr;
  AVIOContext* io = nullptr;
  AVCodecContext* codec = nullptr;
  AVStream* stream = nullptr;
  SwsContext* convert = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  int64_t next_pts = 0;
  bool header_written = false;

  ~Encoder() {
    av_packet_free(&packet);
    av_frame_free(&frame);
    sws_freeContext(convert);
    avcodec_free_context(&codec);
    if (format != nullptr) avformat_free_context(format);
    if (io != nullptr) {
      av_freep(&io->buffer);
      avio_context_free(&io);
    }
  }

  // Sends `input` (null: flush) and muxes every packet the encoder gives back.
  int encode(const AVFrame* input) {
    int rc = avcodec_send_frame(codec, input);
    while (rc >= 0) {
      rc = avcodec_receive_packet(codec, packet);
      if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) return 0;
      if (rc < 0) return rc;
      av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
      packet->stream_index = stream->index;
      rc = av_interleaved_write_frame(format, packet);
    }
    return rc;
  }
};

void* encoder_open(const imx_movie_settings* s, const imx_movie_output* output, char* error,
                   size_t error_size) {
  quiet_ffmpeg();
  std::unique_ptr<Encoder> e(new (std::nothrow) Encoder);
  if (!e) {
    say(error, error_size, "out of memory");
    return nullptr;
  }
  e->output = *output;
  const AVCodec* codec = avcodec_find_encoder_by_name(s->encoder);
  if (codec == nullptr) {
    say(error, error_size,
        std::string("this FFmpeg (libavcodec ") + AV_STRINGIFY(LIBAVCODEC_VERSION) +
            ") has no encoder " + s->encoder);
    return nullptr;
  }
  const AVPixelFormat pixels = av_get_pix_fmt(s->pixel_format);
  int rc = avformat_alloc_output_context2(&e->format, nullptr, s->container, nullptr);
  if (rc < 0 || e->format == nullptr) {
    say(error, error_size, std::string("libavformat has no muxer ") + s->container);
    return nullptr;
  }
  const int buffer_size = 1 << 16;
  auto* buffer = static_cast<unsigned char*>(av_malloc(buffer_size));
  e->io = buffer != nullptr ? avio_alloc_context(buffer, buffer_size, 1, &e->output, nullptr,
                                                 write_packet, seek_output)
                            : nullptr;
  if (e->io == nullptr) {
    av_free(buffer);
    say(error, error_size, "out of memory");
    return nullptr;
  }
  e->format->pb = e->io;
  e->format->flags |= AVFMT_FLAG_CUSTOM_IO;
  e->stream = avformat_new_stream(e->format, nullptr);
  e->codec = avcodec_alloc_context3(codec);
  e->frame = av_frame_alloc();
  e->packet = av_packet_alloc();
  if (e->stream == nullptr || e->codec == nullptr || e->frame == nullptr || e->packet == nullptr) {
    say(error, error_size, "out of memory");
    return nullptr;
  }
  AVCodecContext* c = e->codec;
  c->width = s->width;
  c->height = s->height;
  c->pix_fmt = pixels;
  c->time_base = AVRational{s->fps_den, s->fps_num};
  c->framerate = AVRational{s->fps_num, s->fps_den};
  c->gop_size = std::max(1, 2 * s->fps_num / std::max(1, s->fps_den));  // a key frame each 2 s
  const bool rgb = (av_pix_fmt_desc_get(pixels)->flags & AV_PIX_FMT_FLAG_RGB) != 0;
  c->color_range = rgb ? AVCOL_RANGE_JPEG : AVCOL_RANGE_MPEG;
  c->colorspace = rgb ? AVCOL_SPC_RGB : AVCOL_SPC_BT709;
  c->color_primaries = AVCOL_PRI_BT709;   // sRGB's primaries
  c->color_trc = AVCOL_TRC_IEC61966_2_1;  // the frames are sRGB-encoded
  if (e->format->oformat->flags & AVFMT_GLOBALHEADER) c->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  AVDictionary* options = nullptr;
  if (s->options != nullptr && s->options[0] != '\0')
    av_dict_parse_string(&options, s->options, "=", ":", 0);
  rc = avcodec_open2(c, codec, &options);
  av_dict_free(&options);
  if (rc < 0) {
    say(error, error_size,
        std::string("cannot open the ") + s->encoder + " encoder: " + av_message(rc));
    return nullptr;
  }
  avcodec_parameters_from_context(e->stream->codecpar, c);
  e->stream->time_base = c->time_base;
  e->stream->avg_frame_rate = c->framerate;
  e->convert = sws_getContext(s->width, s->height, AV_PIX_FMT_RGB24, s->width, s->height, pixels,
                              SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, nullptr, nullptr,
                              nullptr);
  if (e->convert == nullptr) {
    say(error, error_size, std::string("libswscale cannot convert RGB to ") + s->pixel_format);
    return nullptr;
  }
  if (!rgb)
    sws_setColorspaceDetails(e->convert, sws_getCoefficients(SWS_CS_ITU709), 1,
                             sws_getCoefficients(SWS_CS_ITU709), 0, 0, 1 << 16, 1 << 16);
  e->frame->format = pixels;
  e->frame->width = s->width;
  e->frame->height = s->height;
  e->frame->color_range = c->color_range;
  e->frame->colorspace = c->colorspace;
  e->frame->color_primaries = c->color_primaries;
  e->frame->color_trc = c->color_trc;
  rc = av_frame_get_buffer(e->frame, 0);
  if (rc >= 0) rc = avformat_write_header(e->format, nullptr);
  if (rc < 0) {
    say(error, error_size, "cannot start the movie: " + av_message(rc));
    return nullptr;
  }
  e->header_written = true;
  return e.release();
}

int32_t encoder_add(void* handle, const uint8_t* rgb, char* error, size_t error_size) {
  t_last_log.clear();
  auto* e = static_cast<Encoder*>(handle);
  int rc = av_frame_make_writable(e->frame);
  if (rc >= 0) {
    const uint8_t* planes[1] = {rgb};
    const int strides[1] = {3 * e->codec->width};
    sws_scale(e->convert, planes, strides, 0, e->codec->height, e->frame->data, e->frame->linesize);
    e->frame->pts = e->next_pts++;
    rc = e->encode(e->frame);
  }
  if (rc < 0) {
    say(error, error_size, "encoding a frame failed: " + av_message(rc));
    return 1;
  }
  return 0;
}

int32_t encoder_finish(void* handle, char* error, size_t error_size) {
  t_last_log.clear();
  auto* e = static_cast<Encoder*>(handle);
  int rc = e->encode(nullptr);
  if (rc >= 0) rc = av_write_trailer(e->format);
  if (rc >= 0) avio_flush(e->io);
  if (rc >= 0 && e->io->error < 0) rc = e->io->error;
  if (rc < 0) {
    say(error, error_size, "finishing the movie failed: " + av_message(rc));
    return 1;
  }
  return 0;
}

void encoder_close(void* handle) {
  delete static_cast<Encoder*>(handle);
}

// ---- decoding --------------------------------------------------------------------------------

struct Reader {
  AVFormatContext* format = nullptr;
  AVCodecContext* codec = nullptr;
  SwsContext* convert = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  int stream = -1;
  bool draining = false;

  ~Reader() {
    av_packet_free(&packet);
    av_frame_free(&frame);
    sws_freeContext(convert);
    avcodec_free_context(&codec);
    avformat_close_input(&format);
  }
};

int sws_colourspace(AVColorSpace space) {
  switch (space) {
    case AVCOL_SPC_BT709:
      return SWS_CS_ITU709;
    case AVCOL_SPC_BT2020_NCL:
    case AVCOL_SPC_BT2020_CL:
      return SWS_CS_BT2020;
    case AVCOL_SPC_SMPTE240M:
      return SWS_CS_SMPTE240M;
    default:
      return SWS_CS_DEFAULT;
  }
}

void* reader_open(const char* path, imx_movie_info* info, char* error, size_t error_size) {
  quiet_ffmpeg();
  std::unique_ptr<Reader> r(new (std::nothrow) Reader);
  if (!r) {
    say(error, error_size, "out of memory");
    return nullptr;
  }
  int rc = avformat_open_input(&r->format, path, nullptr, nullptr);
  if (rc >= 0) rc = avformat_find_stream_info(r->format, nullptr);
  if (rc < 0) {
    say(error, error_size, "not a movie libavformat reads: " + av_message(rc));
    return nullptr;
  }
  const AVCodec* codec = nullptr;
  r->stream = av_find_best_stream(r->format, AVMEDIA_TYPE_VIDEO, -1, -1, &codec, 0);
  if (r->stream < 0 || codec == nullptr) {
    say(error, error_size, "no video stream libavcodec decodes");
    return nullptr;
  }
  const AVStream* stream = r->format->streams[r->stream];
  r->codec = avcodec_alloc_context3(codec);
  r->frame = av_frame_alloc();
  r->packet = av_packet_alloc();
  if (r->codec == nullptr || r->frame == nullptr || r->packet == nullptr) {
    say(error, error_size, "out of memory");
    return nullptr;
  }
  rc = avcodec_parameters_to_context(r->codec, stream->codecpar);
  if (rc >= 0) rc = avcodec_open2(r->codec, codec, nullptr);
  if (rc < 0) {
    say(error, error_size, "cannot open the decoder: " + av_message(rc));
    return nullptr;
  }
  info->width = r->codec->width;
  info->height = r->codec->height;
  info->fps_num = stream->avg_frame_rate.num;
  info->fps_den = stream->avg_frame_rate.den;
  std::snprintf(info->codec, sizeof info->codec, "%s", codec->name);
  const char* pixels = av_get_pix_fmt_name(r->codec->pix_fmt);
  std::snprintf(info->pixel_format, sizeof info->pixel_format, "%s", pixels ? pixels : "?");
  return r.release();
}

// The decoded frame as RGB24 rows, converted with the matrix and range the stream states.
int32_t convert_frame(Reader* r, uint8_t* rgb, char* error, size_t error_size) {
  const AVFrame* f = r->frame;
  if (f->width != r->codec->width || f->height != r->codec->height) {
    say(error, error_size, "a frame changes the movie's size");
    return -1;
  }
  r->convert = sws_getCachedContext(
      r->convert, f->width, f->height, static_cast<AVPixelFormat>(f->format), f->width, f->height,
      AV_PIX_FMT_RGB24, SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, nullptr, nullptr,
      nullptr);
  if (r->convert == nullptr) {
    say(error, error_size, "libswscale cannot convert the frames to RGB");
    return -1;
  }
  const int* table = sws_getCoefficients(sws_colourspace(f->colorspace));
  sws_setColorspaceDetails(r->convert, table, f->color_range == AVCOL_RANGE_JPEG, table, 1, 0,
                           1 << 16, 1 << 16);
  uint8_t* planes[1] = {rgb};
  const int strides[1] = {3 * f->width};
  sws_scale(r->convert, f->data, f->linesize, 0, f->height, planes, strides);
  return 1;
}

int32_t reader_next(void* handle, uint8_t* rgb, char* error, size_t error_size) {
  t_last_log.clear();
  auto* r = static_cast<Reader*>(handle);
  while (true) {
    int rc = avcodec_receive_frame(r->codec, r->frame);
    if (rc >= 0) return convert_frame(r, rgb, error, error_size);
    if (rc == AVERROR_EOF) return 0;
    if (rc != AVERROR(EAGAIN)) {
      say(error, error_size, "decoding failed: " + av_message(rc));
      return -1;
    }
    if (r->draining) return 0;
    rc = av_read_frame(r->format, r->packet);
    if (rc == AVERROR_EOF) {
      r->draining = true;
      avcodec_send_packet(r->codec, nullptr);
      continue;
    }
    if (rc < 0) {
      say(error, error_size, "reading failed: " + av_message(rc));
      return -1;
    }
    if (r->packet->stream_index == r->stream) rc = avcodec_send_packet(r->codec, r->packet);
    av_packet_unref(r->packet);
    if (rc < 0 && rc != AVERROR(EAGAIN)) {
      say(error, error_size, "decoding failed: " + av_message(rc));
      return -1;
    }
  }
}

void reader_close(void* handle) {
  delete static_cast<Reader*>(handle);
}

// ---- the table -------------------------------------------------------------------------------

const char* versions() {
  static const std::string text =
      "libavcodec " AV_STRINGIFY(LIBAVCODEC_VERSION) ", libavformat " AV_STRINGIFY(
          LIBAVFORMAT_VERSION) ", libswscale " AV_STRINGIFY(LIBSWSCALE_VERSION);
  return text.c_str();
}

int32_t has_encoder(const char* name) {
  return avcodec_find_encoder_by_name(name) != nullptr ? 1 : 0;
}

const imx_movie_ffmpeg_calls kCalls{versions,    has_encoder,    encoder_open,
                                    encoder_add, encoder_finish, encoder_close,
                                    reader_open, reader_next,    reader_close};

}  // namespace

extern "C" {

__attribute__((visibility("default"))) uint32_t imx_movie_ffmpeg_abi(void) {
  return IMX_MOVIE_FFMPEG_ABI_VERSION;
}

__attribute__((visibility("default"))) const imx_movie_ffmpeg_calls* imx_movie_ffmpeg_calls(void) {
  return &kCalls;
}
}
