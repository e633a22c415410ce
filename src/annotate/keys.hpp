// Colour bars and legends placed together: side by side in a corner of the image, or beside it on
// a canvas widened to fit them (ColourBarStyle), the bars first.
#pragma once
#include <span>
#include <vector>

#include "annotate/colour_bar.hpp"
#include "annotate/legend.hpp"

namespace imx {

struct KeyPlacements {
  std::vector<ColourBarPlacement> bars;
  std::vector<LegendPlacement> legends;
};

// Draws the distinct bars (distinct_colour_bars), then the legends, side by side from the
// image's edge (the right edge inwards for right corners; left to right otherwise), each at the
// top or bottom as the position says. In a corner each stands on a translucent dark backdrop with
// white text; `outside` widens the image to the right and draws them over the style's background.
// Keys that do not fit the image's height (or, in a corner, its width) are left out.
KeyPlacements draw_keys(Image& image, std::span<const ColourBar> bars,
                        std::span<const Legend> legends, const TextRaster& text,
                        const ColourBarStyle& style);

// The same with the annotation font (find_font) at the size for the image and style.
KeyPlacements draw_keys(Image& image, std::span<const ColourBar> bars,
                        std::span<const Legend> legends, const ColourBarStyle& style = {});

}  // namespace imx
