#include <cmath>
#include <cstdlib>
#include <cstring>

#include <gtest/gtest.h>
#include <spng.h>

#include "core/colour.hpp"
#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::expect_error;
using test::TempDir;

// Premultiplied linear gradients: colour across, alpha down, with an opaque and a clear row.
Image gradient(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float a = static_cast<float>(y) / static_cast<float>(h - 1);
      glm::vec3 straight(static_cast<float>(x) / static_cast<float>(w - 1),
                         1.0f - static_cast<float>(x) / static_cast<float>(w - 1),
                         0.5f * static_cast<float>((x + y) % 7) / 6.0f);
      img.at(x, y) = glm::vec4(straight * a, a);
    }
  return img;
}

glm::vec4 straight(const glm::vec4& p) {
  return p.a > 0.0f ? glm::vec4(glm::vec3(p) / p.a, p.a) : glm::vec4(0.0f);
}

TEST(Png, SrgbRoundTripWithinOneStep) {
  TempDir dir;
  Image img = gradient(64, 33);
  write_png(img, dir / "g.png");
  Image back = read_png(dir / "g.png");
  ASSERT_EQ(back.width(), 64);
  ASSERT_EQ(back.height(), 33);
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      glm::vec4 a = straight(img.at(x, y)), b = straight(back.at(x, y));
      EXPECT_NEAR(a.a, b.a, 0.5f / 255.0f + 1e-6f);
      if (a.a < 1.0f / 255.0f) continue;  // a clear pixel keeps no colour
      // Compared in the file's encoding, where a step is 1/255.
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(srgb_encode(a[c]), srgb_encode(b[c]), 1.0f / 255.0f + 1e-5f)
            << x << "," << y << " channel " << c;
      // And premultiplied again: colour never exceeds alpha.
      EXPECT_LE(back.at(x, y).r, back.at(x, y).a + 1e-6f);
    }
}

TEST(Png, LinearRoundTripWithinOneStep) {
  TempDir dir;
  Image img = gradient(16, 9);
  write_png(img, dir / "lin.png", true);
  Image back = read_png(dir / "lin.png", true);
  for (int y = 1; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(straight(img.at(x, y))[c], straight(back.at(x, y))[c], 1.0f / 255.0f);
}

TEST(Png, OpaqueWhiteAndBlackAreExact) {
  TempDir dir;
  Image img(2, 1);
  img.at(0, 0) = glm::vec4(1.0f);
  img.at(1, 0) = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  write_png(img, dir / "bw.png");
  Image back = read_png(dir / "bw.png");
  EXPECT_EQ(back.at(0, 0), glm::vec4(1.0f));
  EXPECT_EQ(back.at(1, 0), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
}

TEST(Png, NonFiniteAndOutOfRangeValuesAreClamped) {
  TempDir dir;
  Image img(3, 1);
  img.at(0, 0) = glm::vec4(NAN, 0.5f, 2.0f, 1.0f);
  img.at(1, 0) = glm::vec4(0.2f, 0.2f, 0.2f, NAN);
  img.at(2, 0) = glm::vec4(-1.0f, 0.0f, 0.0f, 3.0f);
  write_png(img, dir / "c.png", true);
  Image back = read_png(dir / "c.png", true);
  EXPECT_EQ(back.at(0, 0).r, 0.0f);
  EXPECT_EQ(back.at(0, 0).b, 1.0f);
  EXPECT_EQ(back.at(1, 0), glm::vec4(0.0f));
  EXPECT_EQ(back.at(2, 0), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
}

// PNGs written elsewhere: 16-bit RGBA keeps its precision, grey expands to RGBA.
void encode_png(const std::filesystem::path& file, uint32_t w, uint32_t h, uint8_t depth,
                uint8_t colour_type, const std::vector<uint8_t>& pixels) {
  spng_ctx* ctx = spng_ctx_new(SPNG_CTX_ENCODER);
  spng_set_option(ctx, SPNG_ENCODE_TO_BUFFER, 1);
  spng_ihdr ihdr{};
  ihdr.width = w;
  ihdr.height = h;
  ihdr.bit_depth = depth;
  ihdr.color_type = colour_type;
  spng_set_ihdr(ctx, &ihdr);
  ASSERT_EQ(
      spng_encode_image(ctx, pixels.data(), pixels.size(), SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE), 0);
  size_t size = 0;
  int error = 0;
  void* png = spng_get_png_buffer(ctx, &size, &error);
  test::write_bytes(file, std::string(static_cast<const char*>(png), size));
  std::free(png);
  spng_ctx_free(ctx);
}

TEST(Png, ReadsSixteenBitAndGreyFiles) {
  TempDir dir;
  // One 16-bit pixel R=0x8000, G=0, B=A=0xFFFF; spng takes samples in host byte order.
  uint16_t samples[4] = {0x8000, 0, 0xFFFF, 0xFFFF};
  std::vector<uint8_t> bytes(8);
  std::memcpy(bytes.data(), samples, 8);
  encode_png(dir / "16.png", 1, 1, 16, SPNG_COLOR_TYPE_TRUECOLOR_ALPHA, bytes);
  Image a = read_png(dir / "16.png", true);
  EXPECT_NEAR(a.at(0, 0).r, 32768.0f / 65535.0f, 1e-6f);
  EXPECT_EQ(a.at(0, 0).b, 1.0f);
  EXPECT_EQ(a.at(0, 0).a, 1.0f);
  encode_png(dir / "grey.png", 2, 1, 8, SPNG_COLOR_TYPE_GRAYSCALE, {0, 255});
  Image b = read_png(dir / "grey.png");
  EXPECT_EQ(b.at(0, 0), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
  EXPECT_EQ(b.at(1, 0), glm::vec4(1.0f));
}

TEST(Png, TemporaryFileIsGoneAfterSuccess) {
  TempDir dir;
  write_png(gradient(4, 4), dir / "t.png");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"t.png"});
}

TEST(Png, NonExistentFolderThrowsAndLeavesNothing) {
  TempDir dir;
  expect_error([&] { write_png(gradient(4, 4), dir / "nope" / "x.png"); }, {"x.png"});
  EXPECT_TRUE(dir.entries().empty());
  EXPECT_FALSE(std::filesystem::exists(dir / "nope"));
}

TEST(Png, EmptyImageThrows) {
  TempDir dir;
  expect_error([&] { write_png(Image(), dir / "e.png"); }, {"e.png", "empty"});
  expect_error([&] { write_png(Image(0, 5), dir / "e.png"); }, {"e.png"});
  EXPECT_TRUE(dir.entries().empty());
}

TEST(Png, ReadErrorsNameTheFile) {
  TempDir dir;
  expect_error([&] { read_png(dir / "missing.png"); }, {"missing.png", "no such file"});
  test::write_bytes(dir / "junk.png", "this is not a png at all");
  expect_error([&] { read_png(dir / "junk.png"); }, {"junk.png"});
  // A real PNG cut in half.
  write_png(gradient(64, 64), dir / "full.png");
  std::string bytes = test::read_bytes(dir / "full.png");
  test::write_bytes(dir / "cut.png", bytes.substr(0, bytes.size() / 2));
  expect_error([&] { read_png(dir / "cut.png"); }, {"cut.png"});
}

}  // namespace
}  // namespace imx
