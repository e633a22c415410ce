/* The C interface of the movie plugin (libimx_movie_ffmpeg.so, built from this folder): FFmpeg's
 * libavcodec, libavformat and libswscale encoding RGB frames into MP4, WebM or Matroska, and
 * decoding a movie back to RGB frames. imx_movie opens the plugin with dlopen on the first movie
 * (src/movie/movie_plugin.cpp), so that libavcodec and the dozens of codec libraries behind it
 * are not loaded at every start-up. Plain C: settings, byte buffers and an error string; no C++
 * type or exception crosses it. */
#ifndef IMX_MOVIE_FFMPEG_ABI_H
#define IMX_MOVIE_FFMPEG_ABI_H

#include <stddef.h>
#include <stdint.h>

/* Raised whenever a signature or struct below changes: a plugin of another version is not used. */
#define IMX_MOVIE_FFMPEG_ABI_VERSION 1u

#define IMX_MOVIE_FFMPEG_ABI_SYMBOL "imx_movie_ffmpeg_abi"
#define IMX_MOVIE_FFMPEG_CALLS_SYMBOL "imx_movie_ffmpeg_calls"

/* Where an encoder's bytes go: a seekable output of the caller's (the muxers seek back to write
 * sizes and indexes). `write` returns 0, or non-zero when the bytes could not be written; `seek`
 * takes SEEK_SET, SEEK_CUR or SEEK_END, or IMX_MOVIE_SEEK_SIZE (then returns the output's size),
 * and returns the new position, or -1. */
#define IMX_MOVIE_SEEK_SIZE 0x10000
struct imx_movie_output {
  void* context;
  int32_t (*write)(void* context, const uint8_t* data, int32_t size);
  int64_t (*seek)(void* context, int64_t offset, int32_t whence);
};

/* One movie's encoding. */
struct imx_movie_settings {
  const char* container;    /* libavformat's muxer: "mp4", "webm", "matroska" */
  const char* encoder;      /* libavcodec's encoder: "libx264", "libvpx-vp9", "ffv1" */
  const char* pixel_format; /* what the encoder codes: "yuv420p" (BT.709, limited range), "bgr0" */
  const char* options;      /* the encoder's private options, "key=value:key=value" ("crf=18") */
  int32_t width, height;
  int32_t fps_num, fps_den; /* frames per second, as a fraction */
};

/* What a movie file holds, as its first video stream says. */
struct imx_movie_info {
  int32_t width, height;
  int32_t fps_num, fps_den;
  char codec[64];        /* libavcodec's name of the stream's codec: "h264", "vp9", "ffv1" */
  char pixel_format[32]; /* the stream's pixel format: "yuv420p", "gbrp" */
};

/* The calls. Each that can fail writes a NUL-terminated reason (without the file's name) into
 * `error` (error_size bytes). */
struct imx_movie_ffmpeg_calls {
  /* "libavcodec 59.37.100, libavformat 59.27.100, libswscale 6.7.100": for messages. */
  const char* (*versions)(void);
  /* 1 when libavcodec has an encoder of this name, else 0. */
  int32_t (*has_encoder)(const char* name);
  /* A new movie on `output` (copied; its context must outlive the encoder), or null. */
  void* (*encoder_open)(const struct imx_movie_settings* settings,
                        const struct imx_movie_output* output, char* error, size_t error_size);
  /* Encodes one frame: height rows of width * 3 bytes (8-bit sRGB), the top row first. Returns
   * 0, or non-zero on failure. */
  int32_t (*encoder_add)(void* encoder, const uint8_t* rgb, char* error, size_t error_size);
  /* Flushes the encoder and writes the container's trailer. Returns 0, or non-zero. */
  int32_t (*encoder_finish)(void* encoder, char* error, size_t error_size);
  /* Frees the encoder, finished or not (an unfinished movie is left incomplete). */
  void (*encoder_close)(void* encoder);
  /* Opens a movie file for decoding its first video stream, or null. */
  void* (*reader_open)(const char* path, struct imx_movie_info* info, char* error,
                       size_t error_size);
  /* The next frame as height rows of width * 3 bytes of RGB: returns 1, 0 at the end, or -1 on
   * failure. */
  int32_t (*reader_next)(void* reader, uint8_t* rgb, char* error, size_t error_size);
  void (*reader_close)(void* reader);
};

#ifdef __cplusplus
extern "C" {
#endif

/* Returns IMX_MOVIE_FFMPEG_ABI_VERSION as the plugin was built. */
typedef uint32_t (*imx_movie_ffmpeg_abi_fn)(void);

/* The plugin's calls (static: valid until the process ends). */
typedef const struct imx_movie_ffmpeg_calls* (*imx_movie_ffmpeg_calls_fn)(void);

#ifdef __cplusplus
}
#endif

#endif
