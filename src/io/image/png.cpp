#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <spng.h>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "io/streams/atomic_file.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"

namespace imx {

namespace {

// Images beyond this are corrupt files or not for this renderer (spng's own cap is 2^31-1).
constexpr uint32_t kMaxPngSide = 1u << 16;

// Bytes of the filtered scanlines the IDAT stream inflates to (at least: interlacing adds).
size_t filtered_size(const spng_ihdr& ihdr) {
  int channels = 1;
  if (ihdr.color_type == SPNG_COLOR_TYPE_TRUECOLOR) channels = 3;
  if (ihdr.color_type == SPNG_COLOR_TYPE_GRAYSCALE_ALPHA) channels = 2;
  if (ihdr.color_type == SPNG_COLOR_TYPE_TRUECOLOR_ALPHA) channels = 4;
  const uint64_t row_bits = uint64_t{ihdr.width} * channels * ihdr.bit_depth;
  return static_cast<size_t>(uint64_t{ihdr.height} * (1 + (row_bits + 7) / 8));
}

using SpngContext = std::unique_ptr<spng_ctx, void (*)(spng_ctx*)>;

// [0, 1] to 0..255, rounding to nearest; NaN becomes 0 rather than undefined behaviour.
uint8_t quantize(float v) {
  if (!(v > 0.0f)) return 0;
  if (v >= 1.0f) return 255;
  return static_cast<uint8_t>(std::lround(v * 255.0f));
}

}  // namespace

std::vector<uint8_t> display_rgba8(const Image& image, bool linear) {
  // Premultiplied linear -> straight alpha, then the display encoding, then 8 bits.
  std::vector<uint8_t> rgba(image.size() * 4);
  for (size_t i = 0; i < image.size(); ++i) {
    glm::vec4 p = image.data()[i];
    float a = p.a > 0.0f ? std::min(p.a, 1.0f) : 0.0f;
    glm::vec3 c = a > 0.0f ? glm::vec3(p) / a : glm::vec3(0.0f);
    for (int ch = 0; ch < 3; ++ch) rgba[i * 4 + ch] = quantize(linear ? c[ch] : srgb_encode(c[ch]));
    rgba[i * 4 + 3] = quantize(a);
  }
  return rgba;
}

std::string encode_png(const Image& image, const std::string& what, bool linear,
                       int compression_level) {
  if (image.width() <= 0 || image.height() <= 0 || image.empty())
    throw Error(
        fmt::format("{}: cannot write an empty {}x{} image", what, image.width(), image.height()));
  if (static_cast<uint32_t>(image.width()) > kMaxPngSide ||
      static_cast<uint32_t>(image.height()) > kMaxPngSide)
    throw Error(fmt::format("{}: image {}x{} is larger than {} pixels on a side", what,
                            image.width(), image.height(), kMaxPngSide));
  std::vector<uint8_t> rgba = display_rgba8(image, linear);

  SpngContext ctx(spng_ctx_new(SPNG_CTX_ENCODER), spng_ctx_free);
  if (!ctx) throw Error(fmt::format("{}: out of memory for the PNG encoder", what));
  spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1);
  if (compression_level >= 0)
    spng_set_option(ctx.get(), SPNG_IMG_COMPRESSION_LEVEL, compression_level);
  // Level 0 or 1 asks for speed: one row filter (up) instead of trying all five on every row.
  if (compression_level >= 0 && compression_level <= 1)
    spng_set_option(ctx.get(), SPNG_FILTER_CHOICE, SPNG_FILTER_CHOICE_UP);
  spng_ihdr ihdr{};
  ihdr.width = static_cast<uint32_t>(image.width());
  ihdr.height = static_cast<uint32_t>(image.height());
  ihdr.bit_depth = 8;
  ihdr.color_type = SPNG_COLOR_TYPE_TRUECOLOR_ALPHA;
  int rc = spng_set_ihdr(ctx.get(), &ihdr);
  // Tag the encoding so viewers show the colours as meant: sRGB, or gamma 1 for linear.
  if (rc == 0) rc = linear ? spng_set_gama(ctx.get(), 1.0) : spng_set_srgb(ctx.get(), 0);
  if (rc == 0)
    rc = spng_encode_image(ctx.get(), rgba.data(), rgba.size(), SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
  if (rc != 0) throw Error(fmt::format("{}: PNG encoding failed: {}", what, spng_strerror(rc)));
  size_t size = 0;
  int error = 0;
  std::unique_ptr<void, void (*)(void*)> png(spng_get_png_buffer(ctx.get(), &size, &error),
                                             std::free);
  if (!png || error != 0)
    throw Error(fmt::format("{}: PNG encoding failed: {}", what, spng_strerror(error)));
  return std::string(static_cast<const char*>(png.get()), size);
}

void write_png(const Image& image, const std::filesystem::path& file, bool linear) {
  const std::string png = encode_png(image, file.string(), linear);
  write_file_atomically(file, [&](std::ostream& out) {
    out.write(png.data(), static_cast<std::streamsize>(png.size()));
  });
}

Image read_png(const std::filesystem::path& file, bool linear) {
  const std::string what = file.string();
  InputFd fd = open_input(file, what);
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(::fdopen(fd.get(), "rb"), std::fclose);
  if (!f) throw FileError(fmt::format("{}: cannot open file", what), errno);
  fd.release();  // the FILE closes it
  SpngContext ctx(spng_ctx_new(0), spng_ctx_free);
  if (!ctx) throw Error(fmt::format("{}: out of memory for the PNG decoder", what));
  spng_set_image_limits(ctx.get(), kMaxPngSide, kMaxPngSide);
  // Ancillary chunks (text, ICC) are skipped; cap what they may hold in memory.
  spng_set_chunk_limits(ctx.get(), size_t{1} << 26, size_t{1} << 26);
  int rc = spng_set_png_file(ctx.get(), f.get());
  spng_ihdr ihdr{};
  if (rc == 0) rc = spng_get_ihdr(ctx.get(), &ihdr);
  if (rc != 0) throw Error(fmt::format("{}: not a readable PNG file: {}", what, spng_strerror(rc)));

  // 16-bit files decode at full precision; everything else through 8-bit RGBA.
  bool wide = ihdr.bit_depth == 16;
  int fmt_out = wide ? SPNG_FMT_RGBA16 : SPNG_FMT_RGBA8;
  size_t bytes = 0;
  rc = spng_decoded_image_size(ctx.get(), fmt_out, &bytes);
  if (rc == 0) {
    // The filtered rows are deflated in the file: a tiny file cannot hold a huge image.
    std::error_code ec;
    detail::check_inflatable(filtered_size(ihdr),
                             static_cast<size_t>(std::filesystem::file_size(file, ec)), what);
    check_memory(bytes + uint64_t{ihdr.width} * ihdr.height * sizeof(glm::vec4),
                 fmt::format("{}: a {}x{} PNG", what, ihdr.width, ihdr.height));
  }
  std::vector<uint8_t> buffer(rc == 0 ? bytes : 0);
  if (rc == 0)
    rc = spng_decode_image(ctx.get(), buffer.data(), buffer.size(), fmt_out, SPNG_DECODE_TRNS);
  if (rc != 0) throw Error(fmt::format("{}: PNG decoding failed: {}", what, spng_strerror(rc)));

  Image image(static_cast<int>(ihdr.width), static_cast<int>(ihdr.height));
  for (size_t i = 0; i < image.size(); ++i) {
    float ch[4];
    for (int c = 0; c < 4; ++c) {
      if (wide) {
        uint16_t v;
        std::memcpy(&v, &buffer[(i * 4 + c) * 2], 2);
        ch[c] = static_cast<float>(v) / 65535.0f;
      } else {
        ch[c] = static_cast<float>(buffer[i * 4 + c]) / 255.0f;
      }
    }
    float a = ch[3];
    const glm::vec3 stored(ch[0], ch[1], ch[2]);
    const glm::vec3 rgb = linear ? stored : display_to_linear(stored);
    image.data()[i] = glm::vec4(rgb * a, a);
  }
  return image;
}

}  // namespace imx
