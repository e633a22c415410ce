// Figures for papers, as nilearn draws them, from a scene's volumes: orthogonal cuts through a
// point, a mosaic of cuts along one axis, and a glass brain of three projections; each panel
// with orientation letters and its cut coordinate, the colour bars and legends beside the
// panels. The first volume is the anatomy (grey, through its reading window), the others
// overlays in their transfer functions' colours, as the viewer's reading views show them
// (slice_view.hpp).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "annotate/colour_bar.hpp"
#include "annotate/legend.hpp"
#include "frame/slice_view.hpp"
#include "intermix/image.hpp"
#include "intermix/scene.hpp"

namespace imx {

enum class FigureKind { ortho, mosaic, glass };
std::optional<FigureKind> find_figure_kind(std::string_view name);  // "ortho", "mosaic", "glass"

struct FigureOptions {
  FigureKind kind = FigureKind::ortho;
  // ortho: the point (LPS mm) the three cuts pass through; default the first overlay's peak
  // (largest magnitude), else the anatomy's centre. Kept inside the anatomy's box.
  std::optional<glm::dvec3> cut;
  // mosaic: the cuts' positions along `axis` (LPS mm); default `slices` of them spread evenly
  // over where the first overlay shows (its transfer function's opacity), else the anatomy.
  SliceAxis axis = SliceAxis::axial;
  std::vector<double> cuts;
  int slices = 7;
  int columns = 0;         // mosaic panels per row; 0: one row up to 8, else a near square
  int panel_height = 256;  // pixels of the tallest panel; the others at the same mm per pixel
  bool colorbar = true;    // the overlays' bars beside the panels
  bool annotate = true;    // orientation letters and cut coordinates
  bool crosshair = true;   // ortho: each cut's lines on the other two panels
  bool plot_abs = true;    // glass: the projection of |value|, else of the largest value
};

// One panel: the slice view it shows (for glass, the plane the projection is seen on), its
// top-left pixel in the figure, and its label ("x=12": RAS mm, as MNI coordinates are read).
struct FigurePanel {
  SliceView view;
  int x = 0, y = 0;
  std::string label;
};

struct Figure {
  Image image;  // premultiplied linear RGBA, opaque
  std::vector<FigurePanel> panels;
  std::vector<ColourBarPlacement> bars;
  std::vector<LegendPlacement> legends;  // of overlays that are label maps
};

// The figure of `scene` (at least one volume). Glass: with one volume it is the map and no
// outline is drawn; with more the first is the anatomy whose outline is drawn and the second the
// map. Throws imx::Error for a scene without volumes or options out of range.
Figure render_figure(const Scene& scene, const FigureOptions& options);

// The patient direction a view vector points to: "L", "R", "P", "A", "S" or "I" (LPS world).
const char* orientation_letter(const glm::dvec3& direction);

}  // namespace imx
