#include "annotate/text_raster.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <ft2build.h>
#include FT_FREETYPE_H

#include "intermix/error.hpp"
#include "io/streams/input_file.hpp"

namespace imx {

std::filesystem::path find_font() {
  std::error_code ec;
  if (const char* env = std::getenv("IMX_FONT"); env != nullptr && *env != '\0') {
    if (!std::filesystem::is_regular_file(env, ec))
      throw Error(fmt::format("IMX_FONT={}: no such font file", env));
    return env;
  }
  for (std::string_view candidate : kFontCandidates)
    if (std::filesystem::is_regular_file(candidate, ec)) return std::filesystem::path(candidate);
  throw Error(
      fmt::format("colour bars need a TrueType font and none was found (looked in {}): install "
                  "fonts-dejavu-core or set IMX_FONT to a .ttf file",
                  fmt::join(kFontCandidates, ", ")));
}

struct TextRaster::Face {
  FT_Library library = nullptr;
  FT_Face face = nullptr;
  ~Face() {
    if (face) FT_Done_Face(face);
    if (library) FT_Done_FreeType(library);
  }
};

TextRaster::TextRaster(const std::filesystem::path& font, int pixel_height)
    : face_(std::make_unique<Face>()), pixel_height_(pixel_height) {
  if (FT_Init_FreeType(&face_->library) != 0) throw Error("FreeType failed to start");
  const InputFd fd = open_input(font);  // FreeType opens by name: the checked file's name
  if (const FT_Error e =
          FT_New_Face(face_->library, path_of_open(fd, font).c_str(), 0, &face_->face);
      e != 0)
    throw Error(fmt::format("{}: FreeType cannot open it as a font (error {})", font.string(), e));
  if (FT_Set_Pixel_Sizes(face_->face, 0, static_cast<FT_UInt>(std::clamp(pixel_height, 4, 256))) !=
      0)
    throw Error(fmt::format("{}: no {} px size in this font", font.string(), pixel_height));
}

TextRaster::~TextRaster() = default;

int TextRaster::line_height() const {
  const FT_Size_Metrics& m = face_->face->size->metrics;
  return static_cast<int>((m.ascender - m.descender) >> 6);
}

namespace {

// The next code point of UTF-8 text at `i` (advancing it); '?' for a malformed sequence.
char32_t next_code_point(std::string_view s, size_t& i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char lead = byte(i++);
  if (lead < 0x80) return lead;
  const int extra = lead >= 0xF0 && lead < 0xF8 ? 3 : lead >= 0xE0 ? 2 : lead >= 0xC2 ? 1 : -1;
  if (extra < 0 || i + static_cast<size_t>(extra) > s.size()) return U'?';
  char32_t c = lead & (0x3F >> extra);
  for (int k = 0; k < extra; ++k) {
    if ((byte(i) & 0xC0) != 0x80) return U'?';
    c = (c << 6) | (byte(i++) & 0x3F);
  }
  return c;
}

}  // namespace

TextBitmap TextRaster::render(std::string_view utf8) const {
  FT_Face face = face_->face;
  const FT_Size_Metrics& m = face->size->metrics;
  TextBitmap out;
  out.baseline = static_cast<int>(m.ascender >> 6);
  out.height = line_height();
  // Two passes: the advances give the width, then the glyphs are drawn into it.
  std::vector<char32_t> text;
  for (size_t i = 0; i < utf8.size();) text.push_back(next_code_point(utf8, i));
  int pen = 0;
  for (char32_t c : text)
    if (FT_Load_Char(face, c, FT_LOAD_DEFAULT) == 0)
      pen += static_cast<int>(face->glyph->advance.x >> 6);
  out.width = pen + 1;  // a glyph may overhang its advance by a pixel
  out.coverage.assign(static_cast<size_t>(out.width) * out.height, 0);
  pen = 0;
  for (char32_t c : text) {
    if (FT_Load_Char(face, c, FT_LOAD_RENDER) != 0) continue;
    const FT_GlyphSlot g = face->glyph;
    const FT_Bitmap& b = g->bitmap;
    for (unsigned row = 0; row < b.rows; ++row)
      for (unsigned col = 0; col < b.width; ++col) {
        const int x = pen + g->bitmap_left + static_cast<int>(col);
        const int y = out.baseline - g->bitmap_top + static_cast<int>(row);
        if (x < 0 || y < 0 || x >= out.width || y >= out.height) continue;
        uint8_t& dst = out.coverage[static_cast<size_t>(y) * out.width + x];
        dst = std::max(dst, b.buffer[static_cast<ptrdiff_t>(row) * b.pitch + col]);
      }
    pen += static_cast<int>(g->advance.x >> 6);
  }
  return out;
}

void draw_text(Image& image, const TextBitmap& text, int x, int y, const glm::vec3& colour) {
  for (int row = 0; row < text.height; ++row)
    for (int col = 0; col < text.width; ++col) {
      const int px = x + col, py = y + row;
      if (px < 0 || py < 0 || px >= image.width() || py >= image.height()) continue;
      const float a = text.coverage[static_cast<size_t>(row) * text.width + col] / 255.0f;
      if (a == 0.0f) continue;
      glm::vec4& dst = image.at(px, py);
      dst = glm::vec4(colour * a, a) + (1.0f - a) * dst;  // premultiplied "over"
    }
}

}  // namespace imx
