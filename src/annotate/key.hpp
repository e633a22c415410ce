// A key: one colour bar or legend, measured before it is drawn, so that keys can be placed as a
// group (keys.hpp): in a corner of the image, or beside it on a widened canvas.
#pragma once
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "intermix/image.hpp"

namespace imx {

// Where keys go: into a corner of the image, over a translucent dark backdrop with white text,
// or beside it, on a canvas widened to the right to fit them, over the background with text
// that contrasts with it (figures' default: keys never cover the objects).
enum class ColourBarPosition { top_right, top_left, bottom_right, bottom_left, outside };
inline constexpr std::array<ColourBarPosition, 5> kColourBarPositions = {
    ColourBarPosition::top_right, ColourBarPosition::top_left, ColourBarPosition::bottom_right,
    ColourBarPosition::bottom_left, ColourBarPosition::outside};
// "top-right", "top-left", "bottom-right", "bottom-left", "outside".
std::optional<ColourBarPosition> find_colour_bar_position(std::string_view name);
const char* colour_bar_position_name(ColourBarPosition position);
std::vector<std::string> colour_bar_position_names();  // in kColourBarPositions' order

struct ColourBarStyle {
  ColourBarPosition position = ColourBarPosition::top_right;
  double scale = 1.0;  // of the text and strip sizes for the image (colour_bar_text_size)
  // The widened canvas's colour (straight linear RGB, opaque), for `outside`.
  glm::vec3 background{0.0f};
};

struct Key {
  int width = 0, height = 0;  // pixels, its padding included
  // Draws the key with its top-left corner at (left, top), its text and lines in `ink`.
  std::function<void(Image& image, int left, int top, const glm::vec3& ink)> draw;
};

// The padding around and inside a key for text `text_height` pixels high.
inline int key_padding(int text_height) {
  return text_height / 2 > 3 ? text_height / 2 : 3;
}

// `colour` over one pixel with `weight` (straight, opaque result); nothing outside the image.
void blend_key_pixel(Image& image, int x, int y, const glm::vec3& colour, float weight);

}  // namespace imx
