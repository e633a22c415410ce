#include "annotate/keys.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace imx {
namespace {

constexpr float kBackdropOpacity = 0.6f;

}  // namespace

std::optional<ColourBarPosition> find_colour_bar_position(std::string_view name) {
  for (ColourBarPosition p : kColourBarPositions)
    if (name == colour_bar_position_name(p)) return p;
  return std::nullopt;
}

const char* colour_bar_position_name(ColourBarPosition position) {
  switch (position) {
    case ColourBarPosition::top_right:
      return "top-right";
    case ColourBarPosition::top_left:
      return "top-left";
    case ColourBarPosition::bottom_right:
      return "bottom-right";
    case ColourBarPosition::bottom_left:
      return "bottom-left";
    case ColourBarPosition::outside:
      return "outside";
  }
  return "top-right";
}

std::vector<std::string> colour_bar_position_names() {
  std::vector<std::string> names;
  for (ColourBarPosition p : kColourBarPositions) names.emplace_back(colour_bar_position_name(p));
  return names;
}

void blend_key_pixel(Image& image, int x, int y, const glm::vec3& colour, float weight) {
  if (x < 0 || y < 0 || x >= image.width() || y >= image.height()) return;
  glm::vec4& dst = image.at(x, y);
  dst = glm::vec4(colour * weight, weight) + (1.0f - weight) * dst;
}

KeyPlacements draw_keys(Image& image, std::span<const ColourBar> bars,
                        std::span<const Legend> legends, const TextRaster& text,
                        const ColourBarStyle& style) {
  const std::vector<ColourBar> unique = distinct_colour_bars(bars);
  KeyPlacements placed;
  placed.bars.resize(unique.size());
  placed.legends.resize(legends.size());
  const int pad = key_padding(text.pixel_height());
  std::vector<Key> keys;
  std::vector<bool> is_bar;
  for (size_t i = 0; i < unique.size(); ++i) {
    keys.push_back(colour_bar_key(unique[i], text, image.height(), &placed.bars[i]));
    is_bar.push_back(true);
  }
  for (size_t i = 0; i < legends.size(); ++i) {
    keys.push_back(legend_key(legends[i], text, image.height() - pad, &placed.legends[i]));
    is_bar.push_back(false);
  }

  // The keys that fit, in order: the first that does not ends the row.
  const bool outside = style.position == ColourBarPosition::outside;
  size_t fitting = 0;
  int total_width = pad;
  for (const Key& k : keys) {
    if (pad + k.height > image.height()) break;
    if (!outside && total_width + k.width + pad > image.width()) break;
    total_width += k.width + pad;
    ++fitting;
  }
  placed.bars.resize(std::min(placed.bars.size(), fitting));
  placed.legends.resize(fitting > unique.size() ? fitting - unique.size() : 0);
  if (fitting == 0) return placed;

  glm::vec3 ink(1.0f);
  if (outside) {  // the canvas grows; the keys stand on the background
    Image wider(image.width() + total_width, image.height(), glm::vec4(style.background, 1.0f));
    for (int y = 0; y < image.height(); ++y)
      std::copy_n(&image.at(0, y), image.width(), &wider.at(0, y));
    const float luminance = glm::dot(style.background, glm::vec3(0.2126f, 0.7152f, 0.0722f));
    ink = glm::vec3(luminance > 0.2f ? 0.0f : 1.0f);
    image = std::move(wider);
  }
  const bool from_left = outside || style.position == ColourBarPosition::top_left ||
                         style.position == ColourBarPosition::bottom_left;
  const bool at_bottom = style.position == ColourBarPosition::bottom_right ||
                         style.position == ColourBarPosition::bottom_left;
  int x_edge = outside ? image.width() - total_width + pad : from_left ? pad : image.width() - pad;
  for (size_t i = 0; i < fitting; ++i) {
    const Key& k = keys[i];
    const int left = from_left ? x_edge : x_edge - k.width;
    x_edge = from_left ? left + k.width + pad : left - pad;
    const int top = at_bottom ? image.height() - pad - k.height : pad;
    if (!outside)
      for (int y = top; y < top + k.height; ++y)
        for (int x = left; x < left + k.width; ++x)
          blend_key_pixel(image, x, y, glm::vec3(0.0f), kBackdropOpacity);
    k.draw(image, left, top, ink);
  }
  return placed;
}

KeyPlacements draw_keys(Image& image, std::span<const ColourBar> bars,
                        std::span<const Legend> legends, const ColourBarStyle& style) {
  if (bars.empty() && legends.empty()) return {};
  const int size =
      static_cast<int>(std::lround(colour_bar_text_size(image.height()) * style.scale));
  const TextRaster text(find_font(), std::clamp(size, 6, 96));
  return draw_keys(image, bars, legends, text, style);
}

}  // namespace imx
