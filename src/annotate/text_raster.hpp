// Text drawn with FreeType from a TrueType font found at run time: the labels of colour bars.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "intermix/image.hpp"

namespace imx {

// Where find_font looks after $IMX_FONT, in order: Debian's and Ubuntu's fonts-dejavu-core, then
// the same font where Arch, Fedora and a local install put it.
inline constexpr std::array<std::string_view, 5> kFontCandidates = {
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu-sans-fonts/DejaVuSans.ttf",
    "/usr/local/share/fonts/DejaVuSans.ttf",
};

// The font for annotations: the file $IMX_FONT names when set (an error when it is missing), else
// the first of kFontCandidates that exists. Throws imx::Error saying where it looked and what to
// install when there is none.
std::filesystem::path find_font();

// A line of text as coverage: width x height bytes (0 transparent .. 255 covered), row 0 at the
// top, the baseline `baseline` rows down.
struct TextBitmap {
  int width = 0, height = 0, baseline = 0;
  std::vector<uint8_t> coverage;
};

// One font at one pixel size. Not thread-safe (FreeType's face is shared state).
class TextRaster {
 public:
  // Throws imx::Error naming the file when FreeType cannot open it as a font.
  TextRaster(const std::filesystem::path& font, int pixel_height);
  ~TextRaster();
  TextRaster(const TextRaster&) = delete;
  TextRaster& operator=(const TextRaster&) = delete;

  // UTF-8 text on one line (invalid bytes draw as '?'); characters the font lacks draw as its
  // missing-glyph box.
  TextBitmap render(std::string_view utf8) const;
  int width(std::string_view utf8) const { return render(utf8).width; }
  int line_height() const;  // ascender - descender, pixels
  int pixel_height() const { return pixel_height_; }

 private:
  struct Face;
  std::unique_ptr<Face> face_;
  int pixel_height_ = 0;
};

// Draws `text` over `image` in `colour` (linear RGB, opaque), its top-left corner at (x, y);
// what falls outside the image is left out.
void draw_text(Image& image, const TextBitmap& text, int x, int y, const glm::vec3& colour);

}  // namespace imx
