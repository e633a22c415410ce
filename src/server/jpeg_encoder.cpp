#include "server/jpeg_encoder.hpp"

#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <jpeglib.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"

namespace imx::server {

namespace {

// libjpeg reports errors by calling error_exit, which would exit() the process: jump back
// instead (the only way out of its C code that unwinds nothing it owns).
struct JpegError {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void on_jpeg_error(j_common_ptr info) {
  auto* error = reinterpret_cast<JpegError*>(info->err);
  info->err->format_message(info, error->message);
  std::longjmp(error->jump, 1);
}

}  // namespace

std::string encode_jpeg(const Image& image, int quality) {
  if (image.empty()) throw Error("JPEG frame: the image is empty");
  const std::vector<uint8_t> rgba = display_rgba8(image);
  // Frames are rendered over an opaque background; drop alpha (premultiplied onto black).
  std::vector<uint8_t> rgb(image.size() * 3);
  for (size_t i = 0; i < image.size(); ++i)
    for (int c = 0; c < 3; ++c)
      rgb[i * 3 + c] = static_cast<uint8_t>((rgba[i * 4 + c] * rgba[i * 4 + 3] + 127) / 255);

  jpeg_compress_struct info{};
  JpegError error{};
  info.err = jpeg_std_error(&error.manager);
  error.manager.error_exit = on_jpeg_error;
  unsigned char* buffer = nullptr;  // malloc'ed by jpeg_mem_dest, grown as needed
  unsigned long size = 0;
  if (setjmp(error.jump)) {
    jpeg_destroy_compress(&info);
    std::free(buffer);
    throw Error(fmt::format("JPEG frame: {}", error.message));
  }
  jpeg_create_compress(&info);
  jpeg_mem_dest(&info, &buffer, &size);
  info.image_width = static_cast<JDIMENSION>(image.width());
  info.image_height = static_cast<JDIMENSION>(image.height());
  info.input_components = 3;
  info.in_color_space = JCS_RGB;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, quality, TRUE);
  info.dct_method = JDCT_IFAST;  // frames in motion: speed over the last fraction of a dB
  jpeg_start_compress(&info, TRUE);
  const size_t stride = static_cast<size_t>(image.width()) * 3;
  while (info.next_scanline < info.image_height) {
    JSAMPROW row = rgb.data() + info.next_scanline * stride;
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  jpeg_destroy_compress(&info);
  std::string out(reinterpret_cast<const char*>(buffer), size);
  std::free(buffer);
  return out;
}

}  // namespace imx::server
