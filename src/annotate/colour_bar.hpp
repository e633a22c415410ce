// Colour bars drawn into a rendered image (intermix render --colorbar): one per colour-mapped
// object, with its name, units and ticks. Composited after the render, never in its kernels.
#pragma once
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "annotate/key.hpp"
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

// Draws `bars` as draw_keys (keys.hpp) draws them, without legends: side by side, the first
// nearest the image's edge, sized for the image (text about height / 36 px, 10 to 28, times the
// style's scale), bars equal but for shown_by once (distinct_colour_bars). Returns where each
// drawn bar lies.
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

// One bar as a key for an image `height` pixels high; drawing it records where in *placed.
Key colour_bar_key(const ColourBar& bar, const TextRaster& text, int image_height,
                   ColourBarPlacement* placed);

}  // namespace imx
