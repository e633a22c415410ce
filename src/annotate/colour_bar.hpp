// Colour bars drawn into a rendered image (intermix render --colorbar): one per colour-mapped
// object, with its name, units and ticks. Composited after the render, never in its kernels.
#pragma once
#include <array>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec4.hpp>

#include "annotate/text_raster.hpp"
#include "intermix/image.hpp"

namespace imx {

// What a colour-mapped object says about itself to get a bar: any kind of object (a volume's
// transfer function, a plane's colour map, a mesh's value overlay) makes one of these
// (scene_colour_bars.hpp) and the drawing needs nothing else.
struct ColourBar {
  std::string name;   // of the values: the volume's
  std::string units;  // "" when unknown
  // The objects that show the values, when not the volume itself (planes: "axial"); several
  // equal bars join theirs ("axial, sagittal"). The title reads "name (units) on shown_by".
  std::string shown_by;
  double lo = 0.0, hi = 1.0;  // the values at the bar's bottom and top, lo < hi
  // The straight linear RGBA an object shows for a value; alpha 0 where it shows nothing, which
  // the bar draws as a grey checkerboard. Called per bar row, only while drawing.
  std::function<glm::vec4(double)> colour;
};

// Where one bar was drawn, for tests and callers that place more: the colour strip's pixels
// [x0, x1) x [y0, y1) (row y0 shows hi, row y1 - 1 shows lo), and each tick's value and its
// label's box.
struct ColourBarPlacement {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double lo = 0.0, hi = 1.0;
  struct Tick {
    double value;
    int label_x0, label_y0, label_x1, label_y1;
  };
  std::vector<Tick> ticks;
  // The value a strip row shows: its centre's, linearly from hi (top) to lo (bottom).
  double value_at_row(int y) const {
    return hi - (static_cast<double>(y - y0) + 0.5) / static_cast<double>(y1 - y0) * (hi - lo);
  }
};

// Tick values for [lo, hi]: the multiples of 1, 2 or 5 x 10^k in it, about five of them (at
// least two: lo and hi themselves when no multiple fits twice).
std::vector<double> colour_bar_ticks(double lo, double hi);
// A tick's label: as many decimals as the tick step needs, no "-0".
std::string tick_label(double value, double step);

// Where bars go: into a corner of the image, over a translucent dark backdrop with white text,
// or beside it, on a canvas extended to the right to fit them, over the background with text
// that contrasts with it (figures' default: the bars never cover the objects).
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
  // The extended canvas's colour (straight linear RGB, opaque), for `outside`.
  glm::vec3 background{0.0f};
};

// Draws `bars` side by side, the first nearest the image's edge, sized for the image (text about
// height / 36 px, 10 to 28, times the style's scale). Bars equal but for shown_by are drawn once
// (distinct_colour_bars). With `outside` the image grows to the right by the bars' width. Returns
// where each drawn bar lies. Bars that do not fit in the image's height (or, in a corner, its
// width) are left out.
std::vector<ColourBarPlacement> draw_colour_bars(Image& image, std::span<const ColourBar> bars,
                                                 const TextRaster& text,
                                                 const ColourBarStyle& style = {});

// The bars draw_colour_bars draws at most: `bars` with repeats (equal name, units, range and
// colours, as three planes through one map give) joined into one, their shown_by listed, and
// bars without a colour or a finite range lo < hi left out.
std::vector<ColourBar> distinct_colour_bars(std::span<const ColourBar> bars);

// A bar's title: "name", "name (units)", "name (units) on shown_by".
std::string colour_bar_title(const ColourBar& bar);

// The same with the annotation font (find_font) at the size for the image and style.
std::vector<ColourBarPlacement> draw_colour_bars(Image& image, std::span<const ColourBar> bars,
                                                 const ColourBarStyle& style = {});

// The text size draw_colour_bars uses for an image `height` pixels high.
int colour_bar_text_size(int height);

}  // namespace imx
