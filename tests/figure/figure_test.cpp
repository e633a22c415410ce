// Figures read back against the volumes themselves: each panel's pixels are the anatomy's
// windowed grey and the map's colours at the pixel's world point (sampled here, trilinearly,
// from the voxels), the cuts pass where asked, a glass brain projects the map's magnitude over
// the anatomy's outline, and the colour bar stands beside the panels.
#include "figure/figure.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "figure/figure_extent.hpp"
#include "intermix/error.hpp"
#include "presets/colormap.hpp"
#include "presets/colormap_tf.hpp"
#include "volume/tf_lut.hpp"

namespace imx {
namespace {

constexpr glm::ivec3 kDims{40, 48, 36};
constexpr double kPitch = 2.0;
const glm::dvec3 kOrigin{-40.0, -50.0, -30.0};  // voxel (0, 0, 0), LPS mm
// The "head": a ramp inside these voxels, 0 (air) outside.
constexpr glm::ivec3 kHeadLo{4, 4, 4}, kHeadHi{35, 43, 31};
// The map's peak: a voxel centre.
constexpr glm::ivec3 kPeak{26, 20, 22};

glm::dvec3 world_of(const glm::dvec3& index) {
  return kOrigin + kPitch * index;
}

float anatomy_value(int i, int j, int k) {
  const bool head = i >= kHeadLo.x && j >= kHeadLo.y && k >= kHeadLo.z && i <= kHeadHi.x &&
                    j <= kHeadHi.y && k <= kHeadHi.z;
  return head ? 1000.0f + 11.0f * i + 7.0f * j + 13.0f * k : 0.0f;
}

float map_value(int i, int j, int k) {
  const glm::dvec3 d = kPitch * (glm::dvec3(i, j, k) - glm::dvec3(kPeak));
  return static_cast<float>(8.0 * std::exp(-glm::dot(d, d) / (2.0 * 6.0 * 6.0)));
}

std::shared_ptr<const VolumeData> grid(float (*value)(int, int, int)) {
  VolumeData v;
  v.dims = kDims;
  std::vector<float> values;
  for (int k = 0; k < kDims.z; ++k)
    for (int j = 0; j < kDims.y; ++j)
      for (int i = 0; i < kDims.x; ++i) values.push_back(value(i, j, k));
  v.voxels = std::move(values);
  v.index_to_world = glm::dmat4(kPitch);
  v.index_to_world[3] = glm::dvec4(kOrigin, 1.0);
  return std::make_shared<const VolumeData>(std::move(v));
}

// The value trilinearly between a grid's voxels at a world point; NaN outside its hull.
double sample(float (*value)(int, int, int), const glm::dvec3& world) {
  const glm::dvec3 p = (world - kOrigin) / kPitch;
  if (glm::any(glm::lessThan(p, glm::dvec3(0.0))) ||
      glm::any(glm::greaterThan(p, glm::dvec3(kDims - 1))))
    return NAN;
  const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(p)), kDims - 2);
  const glm::dvec3 f = p - glm::dvec3(i0);
  double sum = 0.0;
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 o((c & 1), (c >> 1) & 1, (c >> 2) & 1);
    const double w = (o.x ? f.x : 1 - f.x) * (o.y ? f.y : 1 - f.y) * (o.z ? f.z : 1 - f.z);
    sum += w * value(i0.x + o.x, i0.y + o.y, i0.z + o.z);
  }
  return sum;
}

// Whether all eight voxels around a world point are in the head (its ramp is then exact).
bool inside_head(const glm::dvec3& world) {
  const glm::dvec3 p = (world - kOrigin) / kPitch;
  return glm::all(glm::greaterThanEqual(glm::floor(p), glm::dvec3(kHeadLo))) &&
         glm::all(glm::lessThanEqual(glm::ceil(p), glm::dvec3(kHeadHi)));
}

constexpr glm::dvec2 kWindow{1750.0, 2000.0};

Scene figure_scene(bool with_map = true) {
  Scene s;
  VolumeObject anatomy;
  anatomy.name = "anatomy";
  anatomy.data = grid(anatomy_value);
  anatomy.index_to_world = anatomy.data->index_to_world;
  anatomy.display_window = kWindow;
  anatomy.transfer_function.points = {{0.0, glm::vec4(0.0f)}, {3000.0, glm::vec4(1.0f)}};
  s.volumes.push_back(anatomy);
  if (with_map) {
    VolumeObject map;
    map.name = "tmap";
    map.data = grid(map_value);
    map.index_to_world = map.data->index_to_world;
    ColormapTransferFunction c;
    c.map = Colormap::cold_hot;
    c.lo = 3.0;
    c.hi = 8.0;
    c.threshold = 3.0;
    c.symmetric = true;
    c.opacity = 0.8f;
    map.transfer_function = colormap_transfer_function(c);
    s.volumes.push_back(map);
  }
  for (int i = 0; i < static_cast<int>(s.volumes.size()); ++i)
    s.order.push_back({ObjectKind::volume, i});
  return s;
}

FigureOptions plain(FigureKind kind) {
  FigureOptions o;
  o.kind = kind;
  o.annotate = o.crosshair = o.colorbar = false;
  o.panel_height = 96;
  return o;
}

// Every panel pixel against the volumes: grey by the window where the map hides, the map's
// colour where it shows (away from the threshold and the head's edge, where rounding decides).
// Returns how many pixels of each kind were checked.
glm::ivec2 check_panels(const Scene& scene, const Figure& figure) {
  glm::ivec2 checked(0);
  const TransferFunction& tf = scene.volumes[1].transfer_function;
  for (const FigurePanel& panel : figure.panels)
    for (int y = 0; y < panel.view.height; ++y)
      for (int x = 0; x < panel.view.width; ++x) {
        const glm::dvec3 w = panel.view.world(x + 0.5, y + 0.5);
        if (!inside_head(w)) continue;
        const glm::vec3 shown =
            linear_to_display(glm::vec3(figure.image.at(panel.x + x, panel.y + y)));
        const double t = sample(map_value, w);
        if (t < 2.9) {
          const double a = sample(anatomy_value, w);
          const double grey = std::clamp((a - (kWindow.x - kWindow.y / 2)) / kWindow.y, 0.0, 1.0);
          if (std::abs(shown.r - grey) > 1.0 / 255 || std::abs(shown.b - grey) > 1.0 / 255) {
            ADD_FAILURE() << "panel at " << panel.x << " pixel " << x << "," << y << ": grey "
                          << shown.r << ", want " << grey;
            return checked;
          }
          ++checked.x;
        } else if (t > 3.1) {
          const glm::vec3 want = linear_to_display(glm::vec3(evaluate_transfer_function(tf, t)));
          if (glm::any(glm::greaterThan(glm::abs(shown - want), glm::vec3(2.0f / 255)))) {
            ADD_FAILURE() << "panel at " << panel.x << " pixel " << x << "," << y << ": t " << t
                          << " shows " << shown.r << "," << shown.g << "," << shown.b << ", want "
                          << want.r << "," << want.g << "," << want.b;
            return checked;
          }
          ++checked.y;
        }
      }
  return checked;
}

TEST(Figure, OrthoCutsThroughThePeakShowTheVoxelsThere) {
  const Scene scene = figure_scene();
  FigureOptions o = plain(FigureKind::ortho);
  o.annotate = true;  // labels only; letters and labels lie at the panel edges, out of the head
  const Figure f = render_figure(scene, plain(FigureKind::ortho));
  ASSERT_EQ(f.panels.size(), 3u);
  const glm::dvec3 peak = world_of(kPeak);
  EXPECT_EQ(f.panels[0].view.axis, SliceAxis::sagittal);
  EXPECT_EQ(f.panels[1].view.axis, SliceAxis::coronal);
  EXPECT_EQ(f.panels[2].view.axis, SliceAxis::axial);
  for (const FigurePanel& p : f.panels) {
    // The view's plane passes through the peak.
    const glm::dvec3 centre = p.view.world(0.5 * p.view.width, 0.5 * p.view.height);
    EXPECT_NEAR(glm::dot(centre - peak, p.view.normal), 0.0, 1e-9);
    EXPECT_EQ(p.view.height <= 96, true);
  }
  const glm::ivec2 checked = check_panels(scene, f);
  EXPECT_GT(checked.x, 1000);  // anatomy pixels
  EXPECT_GT(checked.y, 50);    // map pixels
  // Labels: RAS coordinates of the cut (x and y negated from LPS).
  const Figure labelled = render_figure(scene, o);
  EXPECT_EQ(labelled.panels[0].label, fmt::format("x={}", std::lround(-peak.x)));
  EXPECT_EQ(labelled.panels[1].label, fmt::format("y={}", std::lround(-peak.y)));
  EXPECT_EQ(labelled.panels[2].label, fmt::format("z={}", std::lround(peak.z)));
}

TEST(Figure, AGivenCutIsKeptInsideTheAnatomy) {
  const Scene scene = figure_scene();
  FigureOptions o = plain(FigureKind::ortho);
  o.cut = glm::dvec3(0.0, 1000.0, 4.0);  // y far outside: clamped to the head's box
  const Figure f = render_figure(scene, o);
  const WorldBox box = anatomy_box(scene.volumes[0]);
  const glm::dvec3 c = f.panels[1].view.world(0.5 * f.panels[1].view.width, 0.0);
  EXPECT_NEAR(c.y, box.hi.y, 1e-9);
  const glm::dvec3 a = f.panels[2].view.world(0.0, 0.0);
  EXPECT_NEAR(a.z, 4.0, 1e-9);
  check_panels(scene, f);
}

TEST(Figure, AnatomyBoxIsTheVoxelsAboveTheBackground) {
  const WorldBox box = anatomy_box(figure_scene().volumes[0]);
  EXPECT_EQ(box.lo, world_of(glm::dvec3(kHeadLo) - 0.5));
  EXPECT_EQ(box.hi, world_of(glm::dvec3(kHeadHi) + 0.5));
  EXPECT_EQ(peak_point(figure_scene().volumes[1]), world_of(kPeak));
}

TEST(Figure, AMosaicSpreadsItsCutsOverWhereTheMapShows) {
  const Scene scene = figure_scene();
  FigureOptions o = plain(FigureKind::mosaic);
  o.slices = 5;
  const Figure f = render_figure(scene, o);
  ASSERT_EQ(f.panels.size(), 5u);
  // The map shows (|t| >= 3) within about 8.4 mm of the peak: every cut within that, in order.
  double last = -1e9;
  for (const FigurePanel& p : f.panels) {
    EXPECT_EQ(p.view.axis, SliceAxis::axial);
    const double z = p.view.world(0, 0).z;
    EXPECT_LT(std::abs(z - world_of(kPeak).z), 8.4 + kPitch);
    EXPECT_GT(z, last);
    last = z;
    EXPECT_EQ(p.y, 0);  // one row
  }
  const glm::ivec2 checked = check_panels(scene, f);
  EXPECT_GT(checked.y, 20);
  // Given cuts, in rows of two.
  o.axis = SliceAxis::coronal;
  o.cuts = {-20.0, 0.0, 16.0};
  o.columns = 2;
  const Figure g = render_figure(scene, o);
  ASSERT_EQ(g.panels.size(), 3u);
  for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(g.panels[i].view.world(0, 0).y, o.cuts[i], 1e-9);
  EXPECT_EQ(g.panels[2].x, 0);
  EXPECT_GT(g.panels[2].y, 0);
  check_panels(scene, g);
}

TEST(Figure, AGlassBrainProjectsTheMagnitudeOverTheOutline) {
  const Scene scene = figure_scene();
  const Figure f = render_figure(scene, plain(FigureKind::glass));
  ASSERT_EQ(f.panels.size(), 3u);
  const TransferFunction& tf = scene.volumes[1].transfer_function;
  const glm::vec3 grey_outline = display_to_linear(glm::vec3(0.35f));
  for (const FigurePanel& p : f.panels) {
    // At the peak's projection: the map's colour of the largest value along that pixel's line
    // (sampled here 0.05 mm apart; the figure samples a voxel apart, so up to 0.25 lower).
    const glm::dvec2 at = glm::floor(p.view.pixel(world_of(kPeak)));
    const glm::dvec3 through = p.view.world(at.x + 0.5, at.y + 0.5);
    double largest = 0.0;
    for (double t = -100.0; t <= 100.0; t += 0.05) {
      const double v = sample(map_value, through + t * glm::normalize(p.view.normal));
      if (std::isfinite(v)) largest = std::max(largest, v);
    }
    EXPECT_GT(largest, 7.0);
    const glm::vec3 shown = linear_to_display(
        glm::vec3(f.image.at(p.x + static_cast<int>(at.x), p.y + static_cast<int>(at.y))));
    const glm::vec3 hi = linear_to_display(glm::vec3(evaluate_transfer_function(tf, largest)));
    const glm::vec3 lo =
        linear_to_display(glm::vec3(evaluate_transfer_function(tf, largest - 0.25)));
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(shown[c], std::min(lo[c], hi[c]) - 2.0f / 255) << slice_axis_name(p.view.axis);
      EXPECT_LE(shown[c], std::max(lo[c], hi[c]) + 2.0f / 255) << slice_axis_name(p.view.axis);
    }
    // The outline: grey exactly on the head's projected edge, white inside and outside it.
    int outline = 0, white = 0;
    for (int y = 0; y < p.view.height; ++y)
      for (int x = 0; x < p.view.width; ++x) {
        const glm::vec3 c(f.image.at(p.x + x, p.y + y));
        if (glm::all(glm::lessThan(glm::abs(c - grey_outline), glm::vec3(1e-4f)))) ++outline;
        if (c == glm::vec3(1.0f)) ++white;
      }
    const double perimeter = 2.0 * (p.view.width + p.view.height);
    EXPECT_GT(outline, 0.5 * perimeter) << slice_axis_name(p.view.axis);
    EXPECT_LT(outline, 1.5 * perimeter);
    EXPECT_GT(white, p.view.width * p.view.height / 2);
  }
  // Without an anatomy: no outline.
  Scene map_only = figure_scene();
  map_only.volumes.erase(map_only.volumes.begin());
  map_only.order.pop_back();
  const Figure bare = render_figure(map_only, plain(FigureKind::glass));
  for (int y = 0; y < bare.image.height(); ++y)
    for (int x = 0; x < bare.image.width(); ++x)
      ASSERT_FALSE(glm::all(glm::lessThan(glm::abs(glm::vec3(bare.image.at(x, y)) - grey_outline),
                                          glm::vec3(1e-4f))));
}

TEST(Figure, TheColourBarStandsBesideThePanels) {
  FigureOptions o = plain(FigureKind::ortho);
  o.colorbar = true;
  const Figure f = render_figure(figure_scene(), o);
  ASSERT_EQ(f.bars.size(), 1u);
  int right = 0;
  for (const FigurePanel& p : f.panels) right = std::max(right, p.x + p.view.width);
  EXPECT_GE(f.bars[0].x0, right);
  EXPECT_EQ(f.bars[0].lo, -8.0);
  EXPECT_EQ(f.bars[0].hi, 8.0);
  // The anatomy alone has no bar, and no map.
  EXPECT_TRUE(render_figure(figure_scene(false), o).bars.empty());
}

TEST(Figure, ALabelMapOverlayHasALegendAndIsCutThroughItsLabels) {
  Scene scene = figure_scene();
  VolumeObject& labels = scene.volumes[1];
  VolumeData d = *labels.data;  // the map's voxels above 4 become label 17, the rest 0
  const VoxelBuffer<float>& values = std::get<VoxelBuffer<float>>(d.voxels);
  std::vector<float> v(values.data(), values.data() + values.size());
  for (float& x : v) x = x > 4.0f ? 17.0f : 0.0f;
  d.voxels = std::move(v);
  labels.data = std::make_shared<const VolumeData>(std::move(d));
  auto map = std::make_shared<LabelMap>();
  map->entries = {{17, "amygdala", glm::vec3(0.9f, 0.7f, 0.1f), 1.0f, true}};
  map->palette_unlisted = false;
  labels.labels = map;
  FigureOptions o = plain(FigureKind::ortho);
  o.colorbar = true;
  const Figure f = render_figure(scene, o);
  ASSERT_EQ(f.legends.size(), 1u);
  ASSERT_EQ(f.legends[0].rows.size(), 1u);
  EXPECT_EQ(f.legends[0].rows[0].name, "amygdala");
  EXPECT_EQ(glm::vec3(f.image.at(f.legends[0].rows[0].swatch_x0, f.legends[0].rows[0].swatch_y0)),
            glm::vec3(0.9f, 0.7f, 0.1f));
  // The cuts pass through the labelled voxels' centre: the peak, the blob being symmetric.
  const glm::dvec3 centre = f.panels[2].view.world(0.5 * f.panels[2].view.width, 0.0);
  EXPECT_NEAR(centre.z, world_of(kPeak).z, 1e-9);
  // The label's colour where it is, opaque.
  const glm::dvec2 at = f.panels[2].view.pixel(world_of(kPeak));
  const glm::vec3 shown(
      f.image.at(f.panels[2].x + static_cast<int>(at.x), f.panels[2].y + static_cast<int>(at.y)));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(shown[c], glm::vec3(0.9f, 0.7f, 0.1f)[c], 1e-5);
}

TEST(Figure, OrientationLettersFollowTheViews) {
  const SliceView axial = slice_view(SliceAxis::axial, {}, 8, 8, 1.0);
  EXPECT_STREQ(orientation_letter(axial.right), "L");
  EXPECT_STREQ(orientation_letter(-axial.right), "R");
  EXPECT_STREQ(orientation_letter(-axial.down), "A");
  const SliceView sagittal = slice_view(SliceAxis::sagittal, {}, 8, 8, 1.0);
  EXPECT_STREQ(orientation_letter(-sagittal.right), "A");
  EXPECT_STREQ(orientation_letter(-sagittal.down), "S");
  EXPECT_STREQ(orientation_letter(sagittal.down), "I");
}

TEST(Figure, BadRequestsAreRefused) {
  const auto message = [](const Scene& s, const FigureOptions& o) {
    try {
      render_figure(s, o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(Scene{}, plain(FigureKind::ortho)),
            "figure: the scene has no volume (the first is the anatomy)");
  FigureOptions o = plain(FigureKind::mosaic);
  o.slices = 0;
  EXPECT_EQ(message(figure_scene(), o), "figure: 0 slices; a mosaic takes 1 to 64");
  o = plain(FigureKind::ortho);
  o.cut = glm::dvec3(NAN, 0, 0);
  EXPECT_EQ(message(figure_scene(), o), "figure: the cut point is not finite");
  o.cut.reset();
  o.panel_height = 100000;
  EXPECT_EQ(message(figure_scene(), o), "figure: panel height 100000 is outside 16 to 4096 pixels");
  // 64 panels of 4096 pixels in one row: refused by its size, before anything is allocated.
  o = plain(FigureKind::mosaic);
  o.slices = 64;
  o.panel_height = 4096;
  EXPECT_NE(message(figure_scene(), o).find("at most 16384 a side"), std::string::npos);
}

}  // namespace
}  // namespace imx
