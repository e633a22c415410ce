#include "figure/figure.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "annotate/keys.hpp"
#include "annotate/scene_colour_bars.hpp"
#include "annotate/text_raster.hpp"
#include "core/colour.hpp"
#include "figure/figure_extent.hpp"
#include "figure/glass_projection.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "scene/reading_planes.hpp"
#include "volume/tf_lut.hpp"

namespace imx {
namespace {

constexpr int kGap = 4;  // pixels between panels
constexpr int kMaxPanels = 64;
constexpr int kMaxFigureSide = 16384;  // PNG writers and viewers balk beyond

// Which LPS axis a view's normal is along.
int normal_axis(SliceAxis axis) {
  return axis == SliceAxis::sagittal ? 0 : axis == SliceAxis::coronal ? 1 : 2;
}

// A cut's coordinate as MNI and RAS tools write it: "x=-12" (RAS = LPS with x and y negated).
std::string cut_label(SliceAxis axis, double lps) {
  const int a = normal_axis(axis);
  const double ras = a < 2 ? -lps : lps;
  return fmt::format("{}={}", "xyz"[a], std::lround(ras) == 0 ? 0 : std::lround(ras));
}

struct PanelSpec {
  SliceAxis axis;
  double cut;  // LPS mm along the normal
  std::string label;
};

// The overlay the figure's defaults follow: the second volume, if any.
const VolumeObject* first_overlay(const Scene& scene) {
  return scene.volumes.size() > 1 ? &scene.volumes[1] : nullptr;
}

std::vector<PanelSpec> ortho_panels(const Scene& scene, const FigureOptions& o,
                                    const WorldBox& box) {
  glm::dvec3 point = box_centre(box);
  if (o.cut) {
    point = *o.cut;
  } else if (const VolumeObject* overlay = first_overlay(scene)) {
    // A map's peak; a label map's labelled voxels' centre (its peak is any labelled voxel).
    if (!overlay->labels)
      point = peak_point(*overlay);
    else if (auto labelled = voxel_box(*overlay, [](double v) { return v != 0.0; }))
      point = box_centre(*labelled);
  }
  point = glm::clamp(point, box.lo, box.hi);
  std::vector<PanelSpec> panels;
  for (SliceAxis a : {SliceAxis::sagittal, SliceAxis::coronal, SliceAxis::axial}) {
    const double cut = point[normal_axis(a)];
    panels.push_back({a, cut, o.annotate ? cut_label(a, cut) : ""});
  }
  return panels;
}

std::vector<PanelSpec> mosaic_panels(const Scene& scene, const FigureOptions& o,
                                     const WorldBox& box) {
  const int a = normal_axis(o.axis);
  std::vector<double> cuts = o.cuts;
  if (cuts.empty()) {
    // Spread over where the overlay shows, else over the anatomy.
    WorldBox span = box;
    if (const VolumeObject* overlay = first_overlay(scene)) {
      const TransferFunction& tf = overlay->transfer_function;
      if (auto shown = voxel_box(
              *overlay, [&](double v) { return evaluate_transfer_function(tf, v).a > 0.0f; }))
        span = *shown;
    }
    const double lo = std::max(span.lo[a], box.lo[a]), hi = std::min(span.hi[a], box.hi[a]);
    for (int i = 0; i < o.slices; ++i)
      cuts.push_back(hi > lo ? lo + (i + 0.5) / o.slices * (hi - lo) : box_centre(box)[a]);
  }
  std::vector<PanelSpec> panels;
  for (double cut : cuts) panels.push_back({o.axis, cut, o.annotate ? cut_label(o.axis, cut) : ""});
  return panels;
}

// The view of a panel: its plane through `cut`, framing the box's in-plane extent.
SliceView panel_view(const PanelSpec& spec, const WorldBox& box, double mm_per_pixel) {
  const SliceView unit = slice_view(spec.axis, box_centre(box), 1, 1, 1.0);
  const glm::dvec3 size = box_size(box);
  const double across = std::abs(glm::dot(size, unit.right));
  const double down = std::abs(glm::dot(size, unit.down));
  glm::dvec3 centre = box_centre(box);
  centre[normal_axis(spec.axis)] = spec.cut;
  return slice_view(spec.axis, centre,
                    std::max(1, static_cast<int>(std::ceil(across / mm_per_pixel))),
                    std::max(1, static_cast<int>(std::ceil(down / mm_per_pixel))), mm_per_pixel);
}

void blend_pixel(Image& image, int x, int y, const glm::vec3& colour, float weight) {
  if (x < 0 || y < 0 || x >= image.width() || y >= image.height()) return;
  glm::vec4& p = image.at(x, y);
  p = glm::vec4(glm::vec3(p) * (1.0f - weight) + colour * weight, 1.0f);
}

// Each other cut's lines across an ortho panel, where they cross it.
void draw_crosshair(Image& image, const FigurePanel& panel, const glm::dvec3& point,
                    const glm::vec3& colour) {
  const glm::dvec2 p = panel.view.pixel(point);
  const int cx = static_cast<int>(std::floor(p.x)), cy = static_cast<int>(std::floor(p.y));
  for (int y = 0; y < panel.view.height; ++y)
    if (cx >= 0 && cx < panel.view.width)
      blend_pixel(image, panel.x + cx, panel.y + y, colour, 0.6f);
  for (int x = 0; x < panel.view.width; ++x)
    if (cy >= 0 && cy < panel.view.height)
      blend_pixel(image, panel.x + x, panel.y + cy, colour, 0.6f);
}

// The letters at the panel's four sides (as the viewer's) and its label at the bottom left.
void draw_panel_text(Image& image, const FigurePanel& panel, const TextRaster& text,
                     const glm::vec3& colour) {
  const SliceView& v = panel.view;
  const int m = 2;
  const TextBitmap top = text.render(orientation_letter(-v.down));
  const TextBitmap bottom = text.render(orientation_letter(v.down));
  const TextBitmap left = text.render(orientation_letter(-v.right));
  const TextBitmap right = text.render(orientation_letter(v.right));
  draw_text(image, top, panel.x + (v.width - top.width) / 2, panel.y + m, colour);
  draw_text(image, bottom, panel.x + (v.width - bottom.width) / 2,
            panel.y + v.height - bottom.height - m, colour);
  draw_text(image, left, panel.x + m, panel.y + (v.height - left.height) / 2, colour);
  draw_text(image, right, panel.x + v.width - right.width - m,
            panel.y + (v.height - right.height) / 2, colour);
  if (!panel.label.empty()) {
    const TextBitmap label = text.render(panel.label);
    draw_text(image, label, panel.x + m, panel.y + v.height - label.height - m, colour);
  }
}

void check_options(const Scene& scene, const FigureOptions& o) {
  if (scene.volumes.empty() || !scene.volumes.front().data)
    throw Error("figure: the scene has no volume (the first is the anatomy)");
  if (o.kind == FigureKind::glass && scene.volumes.size() > 2)
    throw Error(fmt::format(
        "figure: a glass brain shows one map over one anatomy; the scene has {} volumes",
        scene.volumes.size()));
  if (o.panel_height < 16 || o.panel_height > 4096)
    throw Error(
        fmt::format("figure: panel height {} is outside 16 to 4096 pixels", o.panel_height));
  if (o.slices < 1 || o.slices > kMaxPanels)
    throw Error(fmt::format("figure: {} slices; a mosaic takes 1 to {}", o.slices, kMaxPanels));
  if (o.cuts.size() > static_cast<size_t>(kMaxPanels))
    throw Error(fmt::format("figure: {} cuts; a mosaic takes 1 to {}", o.cuts.size(), kMaxPanels));
  if (o.columns < 0 || o.columns > kMaxPanels)
    throw Error(fmt::format("figure: {} columns is outside 0 to {}", o.columns, kMaxPanels));
  for (double c : o.cuts)
    if (!std::isfinite(c)) throw Error("figure: a cut coordinate is not finite");
  if (o.cut && !std::isfinite(o.cut->x + o.cut->y + o.cut->z))
    throw Error("figure: the cut point is not finite");
}

}  // namespace

std::optional<FigureKind> find_figure_kind(std::string_view name) {
  if (name == "ortho") return FigureKind::ortho;
  if (name == "mosaic") return FigureKind::mosaic;
  if (name == "glass") return FigureKind::glass;
  return std::nullopt;
}

const char* orientation_letter(const glm::dvec3& d) {
  const glm::dvec3 a = glm::abs(d);
  const int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
  static constexpr const char* kLetters[3][2] = {{"R", "L"}, {"A", "P"}, {"I", "S"}};
  return kLetters[axis][d[axis] > 0.0 ? 1 : 0];
}

Figure render_figure(const Scene& scene, const FigureOptions& o) {
  check_options(scene, o);
  const bool glass = o.kind == FigureKind::glass;
  const VolumeObject& anatomy = scene.volumes.front();
  const VolumeObject& map = glass ? scene.volumes.back() : anatomy;
  const bool outlined = glass && scene.volumes.size() == 2;
  const WorldBox box = glass && !outlined ? grid_box(map) : anatomy_box(anatomy);

  std::vector<PanelSpec> specs;
  if (o.kind == FigureKind::mosaic)
    specs = mosaic_panels(scene, o, box);
  else if (o.kind == FigureKind::ortho)
    specs = ortho_panels(scene, o, box);
  else
    for (SliceAxis a : {SliceAxis::sagittal, SliceAxis::coronal, SliceAxis::axial})
      specs.push_back({a, box_centre(box)[normal_axis(a)], ""});

  // One scale for every panel, the tallest panel_height pixels high.
  double tallest = 0.0;
  for (const PanelSpec& s : specs)
    tallest = std::max(tallest,
                       std::abs(glm::dot(box_size(box), slice_view(s.axis, {}, 1, 1, 1.0).down)));
  const double mm_per_pixel = std::max(tallest, 1e-6) / o.panel_height;

  Figure figure;
  for (const PanelSpec& s : specs)
    figure.panels.push_back({panel_view(s, box, mm_per_pixel), 0, 0, s.label});

  // Rows of panels, each row as high as its tallest, panels centred in it.
  const int count = static_cast<int>(figure.panels.size());
  const int columns = o.columns > 0 ? o.columns
                      : count <= 8  ? count
                                    : static_cast<int>(std::ceil(std::sqrt(count)));
  int width = 0, height = 0;
  for (int row = 0; row * columns < count; ++row) {
    int x = 0, row_height = 0;
    for (int i = row * columns; i < std::min(count, (row + 1) * columns); ++i)
      row_height = std::max(row_height, figure.panels[static_cast<size_t>(i)].view.height);
    for (int i = row * columns; i < std::min(count, (row + 1) * columns); ++i) {
      FigurePanel& p = figure.panels[static_cast<size_t>(i)];
      p.x = x;
      p.y = height + (row_height - p.view.height) / 2;
      x += p.view.width + kGap;
    }
    width = std::max(width, x - kGap);
    height += row_height + kGap;
  }
  height -= kGap;

  if (width > kMaxFigureSide || height > kMaxFigureSide)
    throw Error(fmt::format("figure: {} x {} pixels; a figure takes at most {} a side (fewer "
                            "panels, columns or a smaller height)",
                            width, height, kMaxFigureSide));
  check_memory(static_cast<uint64_t>(width) * static_cast<uint64_t>(height) * sizeof(glm::vec4),
               fmt::format("figure of {} x {} pixels", width, height));
  const glm::vec3 background(glass ? 1.0f : 0.0f);
  const glm::vec3 ink(glass ? 0.0f : 1.0f);
  figure.image = Image(width, height, glm::vec4(background, 1.0f));
  std::vector<int> shown;
  std::vector<glm::dvec2> windows;
  for (size_t i = 0; i < scene.volumes.size(); ++i) {
    shown.push_back(static_cast<int>(i));
    windows.push_back(reading_window(scene.volumes[i]));
  }
  std::optional<GlassOutline> outline;
  if (outlined)
    if (const std::optional<double> level = background_level(anatomy))
      outline = GlassOutline{&anatomy, *level};
  for (const FigurePanel& p : figure.panels) {
    const Image panel = glass ? glass_projection(map, p.view, box, o.plot_abs, outline)
                              : render_slice(scene, p.view, shown, windows, 1.0f);
    for (int y = 0; y < panel.height(); ++y)
      for (int x = 0; x < panel.width(); ++x) {
        const glm::vec4 c = panel.at(x, y);  // premultiplied: black where nothing is
        figure.image.at(p.x + x, p.y + y) =
            glm::vec4(glm::vec3(c) + background * (1.0f - c.a), 1.0f);
      }
  }

  if (o.kind == FigureKind::ortho && o.crosshair) {
    glm::dvec3 point(0.0);
    for (size_t i = 0; i < specs.size(); ++i) point[normal_axis(specs[i].axis)] = specs[i].cut;
    for (const FigurePanel& p : figure.panels) draw_crosshair(figure.image, p, point, ink * 0.8f);
  }
  if (o.annotate) {
    const TextRaster text(find_font(), std::clamp(o.panel_height / 14, 10, 24));
    for (const FigurePanel& p : figure.panels) draw_panel_text(figure.image, p, text, ink);
  }
  if (o.colorbar) {
    std::vector<ColourBar> bars;
    std::vector<Legend> legends;
    for (size_t i = glass ? scene.volumes.size() - 1 : 1; i < scene.volumes.size(); ++i) {
      if (std::optional<ColourBar> bar = volume_colour_bar(scene.volumes[i])) bars.push_back(*bar);
      if (std::optional<Legend> legend = label_legend(scene.volumes[i]))
        legends.push_back(std::move(*legend));
    }
    const ColourBarStyle style{ColourBarPosition::outside, 1.0, background};
    const KeyPlacements keys = draw_keys(figure.image, bars, legends, style);
    figure.bars = keys.bars;
    figure.legends = keys.legends;
  }
  return figure;
}

}  // namespace imx
