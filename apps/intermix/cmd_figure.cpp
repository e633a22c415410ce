// intermix figure ortho|mosaic|glass ANATOMY [MAP] -o fig.png: a figure for a paper, as
// nilearn's plot_stat_map, plot_anat and plot_glass_brain draw it (src/figure/figure.hpp).
#include <cmath>
#include <cstdio>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "figure/figure.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "presets/colormap.hpp"
#include "presets/colormap_tf.hpp"

namespace imx::cli {
namespace {

struct Options {
  std::string kind, anatomy, map, output, axis = "axial", colormap, label_table;
  std::optional<double> threshold, vmax;
  std::vector<double> cut, cuts;
  int slices = 7, columns = 0, height = 256;
  bool no_colorbar = false, no_annotate = false, no_crosshair = false, positive = false;
  bool labels = false;
};

// RAS mm, as MNI coordinates and nilearn's cut_coords are given, to the scene's LPS.
double lps_along(int axis, double ras) {
  return axis < 2 ? -ras : ras;
}

// The overlay's colours: a colour map from the threshold to vmax (default: its largest
// magnitude), both signs unless --positive (one-sided; a glass brain is always), as stat_map.
void colour_the_map(VolumeObject& map, const Options& o, bool glass) {
  const auto [lo, hi] = map.data->range();
  const double peak = std::max(std::abs(lo), std::abs(hi));
  const bool symmetric = !o.positive && !glass;
  const double threshold = o.threshold.value_or(3.0);
  const double vmax = o.vmax.value_or(symmetric || glass ? peak : hi);
  if (!(vmax > threshold))
    throw Error(
        fmt::format("{}: threshold {:g} is not below the map's {} {:g}: give --threshold "
                    "(and --vmax)",
                    o.map, threshold, o.vmax ? "--vmax" : "largest value", vmax));
  ColormapTransferFunction c;
  const std::string name = o.colormap.empty() ? (symmetric ? "cold-hot" : "hot") : o.colormap;
  c.map = *find_colormap(name);  // --colormap is checked against the names
  c.lo = threshold;
  c.hi = vmax;
  c.threshold = threshold;
  c.symmetric = symmetric;
  map.transfer_function = colormap_transfer_function(c);
}

int run_figure(const Options& o) {
  const std::optional<FigureKind> kind = find_figure_kind(o.kind);
  const bool glass = kind == FigureKind::glass;
  nlohmann::json objects = nlohmann::json::array();
  objects.push_back({{"name", "anatomy"}, {"type", "volume"}, {"source", {{"file", o.anatomy}}}});
  const bool labels = o.labels || !o.label_table.empty();
  if (labels && glass)
    throw Error("--labels: a glass brain projects a map's values; labels show in ortho and mosaic");
  if (!o.map.empty()) {
    nlohmann::json map = {{"name", std::filesystem::path(o.map).stem().stem().string()},
                          {"type", "volume"},
                          {"source", {{"file", o.map}}}};
    if (labels) map["style"] = "labels";  // its table's colours (or the palette), and a legend
    if (!o.label_table.empty()) map["labels"] = {{"file", o.label_table}};
    objects.push_back(map);
  }
  Scene scene = parse_scene(nlohmann::json{{"objects", objects}}.dump(),
                            std::filesystem::current_path(), "intermix figure");
  if ((scene.volumes.size() > 1 && !labels) || glass) {
    Options named = o;
    if (named.map.empty()) named.map = o.anatomy;  // a glass brain of one volume: the map
    colour_the_map(scene.volumes.back(), named, glass);
  }

  FigureOptions f;
  f.kind = *kind;
  f.axis = *find_slice_axis(o.axis);
  const int axis = f.axis == SliceAxis::sagittal ? 0 : f.axis == SliceAxis::coronal ? 1 : 2;
  if (!o.cut.empty())
    f.cut = glm::dvec3(lps_along(0, o.cut[0]), lps_along(1, o.cut[1]), lps_along(2, o.cut[2]));
  for (double c : o.cuts) f.cuts.push_back(lps_along(axis, c));
  f.slices = o.slices;
  f.columns = o.columns;
  f.panel_height = o.height;
  f.colorbar = !o.no_colorbar;
  f.annotate = !o.no_annotate;
  f.crosshair = !o.no_crosshair;
  f.plot_abs = !o.positive;
  const Figure figure = render_figure(scene, f);
  write_png(figure.image, o.output);
  if (!quiet())
    std::fprintf(stderr, "intermix: figure %s: %d panels, %dx%d -> %s\n", o.kind.c_str(),
                 static_cast<int>(figure.panels.size()), figure.image.width(),
                 figure.image.height(), o.output.c_str());
  return 0;
}

}  // namespace

Command add_figure(CLI::App& app) {
  auto o = std::make_shared<Options>();
  app.add_option("kind", o->kind,
                 "ortho (three cuts through a point), mosaic (cuts along one axis) or glass "
                 "(three projections of the map over the anatomy's outline)")
      ->required()
      ->check(CLI::IsMember({"ortho", "mosaic", "glass"}));
  app.add_option("anatomy", o->anatomy,
                 "the anatomical volume (grey); for a glass brain without a map, the map")
      ->required();
  app.add_option("map", o->map,
                 "a map over it (a statistic, PET, ...): coloured above --threshold");
  app.add_option("-o,--output", o->output, "output PNG")->required();
  app.add_option("--threshold", o->threshold,
                 "the map shows where |value| (with --positive, value) is at least this "
                 "(default 3)");
  app.add_option("--vmax", o->vmax, "the top of the map's colours (default: its largest |value|)");
  app.add_option("--colormap", o->colormap,
                 "the map's colour map (default cold-hot, or hot for --positive and glass)")
      ->check(
          CLI::IsMember(std::vector<std::string>(kColormapNames.begin(), kColormapNames.end())));
  app.add_flag("--labels", o->labels,
               "the map is a label map (a segmentation): drawn in the default palette, with a "
               "legend of the labels it holds");
  app.add_option("--label-table", o->label_table,
                 "the label map's colour table (FreeSurfer LUT, ITK-SNAP, Slicer .seg.nrrd): its "
                 "names and colours; implies --labels");
  app.add_flag("--positive", o->positive,
               "one-sided: only values above the threshold (glass: project the largest value, "
               "not the largest magnitude)");
  app.add_option("--cut", o->cut,
                 "ortho: the point the cuts pass through, RAS mm: X,Y,Z "
                 "(default: the map's peak, else the anatomy's centre)")
      ->delimiter(',')
      ->expected(3);
  app.add_option("--axis", o->axis, "mosaic: the axis the cuts step along")
      ->check(CLI::IsMember({"axial", "coronal", "sagittal"}));
  app.add_option("--cuts", o->cuts,
                 "mosaic: the cuts' RAS coordinates along the axis, comma-separated (default: "
                 "--slices of them spread over where the map shows)")
      ->delimiter(',');
  app.add_option("--slices", o->slices, "mosaic: how many cuts (default 7)")
      ->check(CLI::Range(1, 64));
  app.add_option("--columns", o->columns, "mosaic: panels per row (default: one row up to 8)")
      ->check(CLI::Range(0, 64));
  app.add_option("--height", o->height, "pixels of the tallest panel (default 256)")
      ->check(CLI::Range(16, 4096));
  app.add_flag("--no-colorbar", o->no_colorbar, "leave out the colour bar");
  app.add_flag("--no-annotate", o->no_annotate, "leave out orientation letters and coordinates");
  app.add_flag("--no-crosshair", o->no_crosshair, "ortho: leave out the cuts' lines");
  return [o]() { return run_figure(*o); };
}

}  // namespace imx::cli
