// Legends: the names and colours of what a label map or a tractogram's groups show, drawn beside
// the colour bars (colour_bar.hpp places both). Composited after the render, never in its kernels.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "annotate/key.hpp"
#include "annotate/text_raster.hpp"
#include "intermix/scene.hpp"

namespace imx {

struct LegendEntry {
  std::string name;
  glm::vec3 colour{1.0f};  // straight linear RGB, as the object shows it
};

struct Legend {
  std::string title;  // the object's name
  std::vector<LegendEntry> entries;
  size_t left_out = 0;  // entries beyond what a legend lists ("+N more")
};

// The most entries one legend lists; the rest are counted in left_out.
inline constexpr size_t kMaxLegendEntries = 40;

// A label volume's legend: the labels its voxels hold that its map shows, in value order, each
// by its table name (else "label N") and colour. None for a volume without labels, or when no
// label it holds is shown.
std::optional<Legend> label_legend(const VolumeObject& volume);

// A tractogram's legend when it is coloured by group: each group's name and colour (the group's
// own, else the object's colour). None otherwise.
std::optional<Legend> streamline_legend(const StreamlineObject& object);

// Every legend of the scene, in scene order: label volumes that show (or that a shown plane
// shows) and tractograms coloured by group.
std::vector<Legend> scene_legends(const Scene& scene);

// Where a legend was drawn: each row's swatch and its name's box, in entry order ("+N more" has
// no swatch: its box is the text's).
struct LegendPlacement {
  struct Row {
    std::string name;
    int swatch_x0, swatch_y0, swatch_x1, swatch_y1;
    int text_x0, text_y0, text_x1, text_y1;
  };
  std::vector<Row> rows;
};

// A legend as a key, its rows cut to what fits `max_height` pixels (the rest counted in its
// "+N more" row); drawing it records where in *placed.
Key legend_key(const Legend& legend, const TextRaster& text, int max_height,
               LegendPlacement* placed);

}  // namespace imx
