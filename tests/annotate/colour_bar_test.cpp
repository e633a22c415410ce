// Colour bars read back from the image: each strip row's colour is the object's colour at that
// row's value (the transfer function's, or the plane's colour map), to 1/255 after the PNG's
// 8-bit sRGB encoding; the tick labels and title are drawn; bars repeat once.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "annotate/scene_colour_bars.hpp"
#include "core/colour.hpp"
#include "have_font.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "presets/colormap.hpp"
#include "presets/colormap_tf.hpp"
#include "volume/tf_lut.hpp"

namespace imx {
namespace {

constexpr glm::vec4 kBackground{0.2f, 0.3f, 0.4f, 1.0f};

// A t-map volume (symmetric cold-hot over |t| in [3, 8]) and a hot plane through it, thresholded.
Scene overlay_scene() {
  Scene scene;
  VolumeObject tmap;
  tmap.name = "tmap";
  tmap.units = "t";
  ColormapTransferFunction c;
  c.map = Colormap::cold_hot;
  c.lo = 3.0;
  c.hi = 8.0;
  c.threshold = 3.0;
  c.symmetric = true;
  tmap.transfer_function = colormap_transfer_function(c);
  scene.volumes.push_back(tmap);
  scene.order.push_back({ObjectKind::volume, 0});
  PlaneObject plane;
  plane.name = "axial";
  plane.volume = 0;
  plane.window = {5.0, 10.0};  // [0, 10]
  plane.colormap = Colormap::hot;
  plane.threshold = 2.5;
  scene.planes.push_back(plane);
  scene.order.push_back({ObjectKind::plane, 0});
  return scene;
}

using test::have_font;

struct Rgba8 {
  const std::vector<uint8_t>& bytes;
  int width;
  glm::ivec3 at(int x, int y) const {
    const size_t i = 4 * (static_cast<size_t>(y) * width + x);
    return {bytes[i], bytes[i + 1], bytes[i + 2]};
  }
};

glm::ivec3 expected_bytes(const glm::vec3& linear) {
  return {static_cast<int>(std::lround(srgb_encode(linear.r) * 255.0f)),
          static_cast<int>(std::lround(srgb_encode(linear.g) * 255.0f)),
          static_cast<int>(std::lround(srgb_encode(linear.b) * 255.0f))};
}

// Every row of the strip, at its middle column: the object's colour where it shows, the grey
// checkerboard where it does not. Returns how many rows showed colour.
int check_strip(const Rgba8& png, const ColourBarPlacement& p,
                const std::function<glm::vec4(double)>& object_colour, const char* what) {
  int coloured = 0;
  const int x = (p.x0 + p.x1) / 2;
  for (int y = p.y0; y < p.y1; ++y) {
    // The value of row y, from the strip's extent: hi at its top edge, lo at its bottom edge.
    const double v = p.hi - (y - p.y0 + 0.5) / (p.y1 - p.y0) * (p.hi - p.lo);
    const glm::vec4 want = object_colour(v);
    const glm::ivec3 got = png.at(x, y);
    if (want.a > 0.0f) {
      const glm::ivec3 e = expected_bytes(glm::vec3(want));
      for (int c = 0; c < 3; ++c)
        EXPECT_LE(std::abs(got[c] - e[c]), 1) << what << " row " << y << " value " << v;
      ++coloured;
    } else {
      EXPECT_TRUE(got.r == got.g && got.g == got.b) << what << " row " << y << " value " << v;
      EXPECT_LT(got.r, 130) << what << " row " << y;  // the dark checkerboard
    }
  }
  return coloured;
}

TEST(ColourBar, StripColoursAreTheObjectsColoursAtEachRowsValue) {
  ASSERT_TRUE(have_font())
      << "no font for colour bars: scripts/install-deps installs fonts-dejavu-core";
  const Scene scene = overlay_scene();
  const std::vector<ColourBar> bars = scene_colour_bars(scene);
  ASSERT_EQ(bars.size(), 2u);
  Image image(512, 512, kBackground);
  const std::vector<ColourBarPlacement> placed = draw_colour_bars(image, bars);
  ASSERT_EQ(placed.size(), 2u);
  const std::vector<uint8_t> bytes = display_rgba8(image);
  const Rgba8 png{bytes, image.width()};

  // The volume's bar spans its transfer function's shown values, -8 .. 8.
  EXPECT_EQ(placed[0].lo, -8.0);
  EXPECT_EQ(placed[0].hi, 8.0);
  const TransferFunction& tf = scene.volumes[0].transfer_function;
  const int volume_rows = check_strip(
      png, placed[0], [&](double v) { return evaluate_transfer_function(tf, v); }, "tmap");
  // |t| < 3 hidden: 6 of 16 units of the strip show nothing.
  const int rows = placed[0].y1 - placed[0].y0;
  EXPECT_NEAR(volume_rows, rows * 10.0 / 16.0, 2.0);

  // The plane's bar spans its window [0, 10]; below 2.5 nothing, above hot at (v - 0) / 10.
  EXPECT_EQ(placed[1].lo, 0.0);
  EXPECT_EQ(placed[1].hi, 10.0);
  const int plane_rows = check_strip(
      png, placed[1],
      [](double v) {
        return v >= 2.5 ? glm::vec4(colormap_rgb(Colormap::hot, static_cast<float>(v / 10.0)), 1.0f)
                        : glm::vec4(0.0f);
      },
      "plane");
  EXPECT_NEAR(plane_rows, (placed[1].y1 - placed[1].y0) * 0.75, 2.0);
  // Side by side from the right edge.
  EXPECT_GT(placed[0].x0, placed[1].x1);
  EXPECT_LT(placed[0].x1, image.width());
}

TEST(ColourBar, TickLabelsAreDrawnInTheirBoxes) {
  ASSERT_TRUE(have_font())
      << "no font for colour bars: scripts/install-deps installs fonts-dejavu-core";
  const Scene scene = overlay_scene();
  const std::vector<ColourBar> bars = scene_colour_bars(scene);
  Image image(512, 512, kBackground);
  const std::vector<ColourBarPlacement> placed = draw_colour_bars(image, bars);
  ASSERT_FALSE(placed.empty());
  // -8 .. 8 in steps of 5 (about five ticks of 1, 2 or 5 x 10^k).
  ASSERT_EQ(placed[0].ticks.size(), 3u);
  EXPECT_EQ(placed[0].ticks[0].value, -5.0);
  EXPECT_EQ(placed[0].ticks[2].value, 5.0);
  // The translucent dark panel (black at 0.6) over the opaque background.
  const glm::vec4 panel(0.4f * glm::vec3(kBackground), 1.0f);
  for (const ColourBarPlacement& p : placed)
    for (const ColourBarPlacement::Tick& t : p.ticks) {
      int text_pixels = 0, panel_pixels = 0;
      for (int y = t.label_y0; y < t.label_y1; ++y)
        for (int x = t.label_x0; x < t.label_x1; ++x) {
          const glm::vec4 c = image.at(x, y);
          if (c.r > panel.r + 0.3f && c.g > panel.g + 0.3f) ++text_pixels;  // white-ish
          if (glm::all(glm::lessThan(glm::abs(c - panel), glm::vec4(1e-5f)))) ++panel_pixels;
        }
      EXPECT_GE(text_pixels, 4) << "tick " << t.value;
      EXPECT_GT(panel_pixels, 0) << "tick " << t.value;  // text, not a filled box
    }
  // Nothing drawn outside the panels' columns: the left half is untouched.
  for (int y = 0; y < image.height(); y += 7)
    for (int x = 0; x < image.width() / 2; x += 7) ASSERT_EQ(image.at(x, y), kBackground);
}

TEST(ColourBar, EqualBarsAreDrawnOnce) {
  ASSERT_TRUE(have_font())
      << "no font for colour bars: scripts/install-deps installs fonts-dejavu-core";
  Scene scene = overlay_scene();
  for (int i = 1; i <= 2; ++i) {  // coronal and sagittal planes through the same map
    scene.planes.push_back(scene.planes[0]);
    scene.planes.back().name = i == 1 ? "coronal" : "sagittal";
    scene.order.push_back({ObjectKind::plane, i});
  }
  const std::vector<ColourBar> bars = scene_colour_bars(scene);
  EXPECT_EQ(bars.size(), 4u);
  const std::vector<ColourBar> distinct = distinct_colour_bars(bars);
  ASSERT_EQ(distinct.size(), 2u);
  EXPECT_EQ(colour_bar_title(distinct[0]), "tmap (t)");
  EXPECT_EQ(colour_bar_title(distinct[1]), "tmap (t) on axial, coronal, sagittal");
  Image image(512, 512, kBackground);
  EXPECT_EQ(draw_colour_bars(image, bars).size(), 2u);
  scene.planes[2].threshold = 4.0;  // now a different bar
  EXPECT_EQ(distinct_colour_bars(scene_colour_bars(scene)).size(), 3u);
}

TEST(ColourBar, WhichObjectsAskForOne) {
  Scene scene = overlay_scene();
  VolumeObject& v = scene.volumes[0];
  // The shown span only: a transfer function zero beyond [100, 300].
  v.transfer_function.points = {{0.0, glm::vec4(0.0f)},
                                {100.0, glm::vec4(0.0f)},
                                {200.0, glm::vec4(1.0f, 0.0f, 0.0f, 0.5f)},
                                {300.0, glm::vec4(0.0f)},
                                {1000.0, glm::vec4(0.0f)}};
  std::optional<ColourBar> bar = volume_colour_bar(v);
  ASSERT_TRUE(bar);
  EXPECT_EQ(bar->lo, 100.0);
  EXPECT_EQ(bar->hi, 300.0);
  EXPECT_EQ(bar->units, "t");
  for (TfPoint& p : v.transfer_function.points) p.rgba.a = 0.0f;  // hidden
  EXPECT_FALSE(volume_colour_bar(v));
  v.transfer_function.points = {{5.0, glm::vec4(1.0f)}};  // one value (a label volume's)
  EXPECT_FALSE(volume_colour_bar(v));
  PlaneObject grey = scene.planes[0];
  grey.colormap = Colormap::grey;
  grey.threshold.reset();
  EXPECT_FALSE(plane_colour_bar(scene, grey));  // the anatomy underneath
  grey.threshold = 1.0;  // thresholded anatomy (the head without the air around it)
  EXPECT_FALSE(plane_colour_bar(scene, grey));
  grey.colormap = Colormap::red_yellow;
  EXPECT_TRUE(plane_colour_bar(scene, grey));
  PlaneObject hidden = scene.planes[0];
  hidden.opacity = 0.0f;
  EXPECT_FALSE(plane_colour_bar(scene, hidden));
}

TEST(ColourBar, TicksAreRoundNumbersAndLabelsTheirDecimals) {
  EXPECT_EQ(colour_bar_ticks(3.0, 8.0), (std::vector<double>{3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(colour_bar_ticks(-1000.0, 3000.0), (std::vector<double>{-1000, 0, 1000, 2000, 3000}));
  EXPECT_EQ(colour_bar_ticks(0.0, 0.7), (std::vector<double>{0.0, 0.2, 0.4, 0.6000000000000001}));
  EXPECT_FALSE(std::signbit(colour_bar_ticks(-8.0, 8.0)[1]));  // 0, not -0
  const std::vector<double> small = colour_bar_ticks(0.0, 0.5);
  ASSERT_EQ(small.size(), 6u);
  EXPECT_NEAR(small[3], 0.3, 1e-12);
  EXPECT_EQ(tick_label(small[3], 0.1), "0.3");
  EXPECT_EQ(tick_label(-1e-17, 0.1), "0.0");
  EXPECT_EQ(tick_label(2000.0, 1000.0), "2000");
  // A narrow range far from 0: labels with enough decimals to differ.
  const std::vector<double> narrow = colour_bar_ticks(1.0, 1.0001);
  ASSERT_EQ(narrow.size(), 6u);
  EXPECT_EQ(tick_label(narrow[1], narrow[1] - narrow[0]), "1.00002");
  EXPECT_EQ(colour_bar_ticks(5.0, 5.0), (std::vector<double>{5.0, 5.0}));
}

TEST(TextRaster, FontSearchAndBadFontsFailWithOneLine) {
  const char* old = std::getenv("IMX_FONT");
  const std::string saved = old ? old : "";
  setenv("IMX_FONT", "/nonexistent/font.ttf", 1);
  try {
    find_font();
    ADD_FAILURE() << "a missing IMX_FONT was accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "IMX_FONT=/nonexistent/font.ttf: no such font file");
  }
  if (old)
    setenv("IMX_FONT", saved.c_str(), 1);
  else
    unsetenv("IMX_FONT");
  // A file that is not a font.
  try {
    TextRaster t("/proc/self/cmdline", 12);
    ADD_FAILURE() << "a non-font was opened";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("FreeType cannot open it as a font"), std::string::npos);
  }
}

TEST(ColourBar, OutsideTheImageTheCanvasGrowsAndTheImageIsKept) {
  ASSERT_TRUE(have_font())
      << "no font for colour bars: scripts/install-deps installs fonts-dejavu-core";
  const std::vector<ColourBar> bars = scene_colour_bars(overlay_scene());
  Image image(300, 256, kBackground);
  image.at(299, 0) = glm::vec4(1.0f, 0.0f, 0.0f, 1.0f);  // the corner bars would cover
  const glm::vec3 white(1.0f);
  const std::vector<ColourBarPlacement> placed =
      draw_colour_bars(image, bars, ColourBarStyle{ColourBarPosition::outside, 1.0, white});
  ASSERT_EQ(placed.size(), 2u);
  ASSERT_GT(image.width(), 300);
  EXPECT_EQ(image.height(), 256);
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 300; ++x)
      ASSERT_EQ(image.at(x, y), x == 299 && y == 0 ? glm::vec4(1, 0, 0, 1) : kBackground);
  for (const ColourBarPlacement& p : placed) {
    EXPECT_GE(p.x0, 300);
    EXPECT_LE(p.x1, image.width());
  }
  EXPECT_LT(placed[0].x0, placed[1].x0);  // outwards from the image
  // On white, the text is dark: some label pixels are near black.
  int dark = 0;
  for (const ColourBarPlacement::Tick& t : placed[0].ticks)
    for (int y = t.label_y0; y < t.label_y1; ++y)
      for (int x = t.label_x0; x < t.label_x1; ++x) dark += image.at(x, y).r < 0.2f;
  EXPECT_GT(dark, 4);
}

TEST(ColourBar, TheScaleSizesTextAndStrips) {
  ASSERT_TRUE(have_font())
      << "no font for colour bars: scripts/install-deps installs fonts-dejavu-core";
  const std::vector<ColourBar> bars = scene_colour_bars(overlay_scene());
  Image one(512, 512, kBackground), two(512, 512, kBackground);
  const auto a = draw_colour_bars(one, bars, ColourBarStyle{ColourBarPosition::outside, 1.0});
  const auto b = draw_colour_bars(two, bars, ColourBarStyle{ColourBarPosition::outside, 2.0});
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  EXPECT_EQ(b[0].x1 - b[0].x0, 2 * (a[0].x1 - a[0].x0));  // the strip is as wide as the text
  EXPECT_GT(two.width() - 512, 3 * (one.width() - 512) / 2);
}

TEST(ColourBar, ACornerPutsTheBarsThere) {
  ASSERT_TRUE(have_font())
      << "no font for colour bars: scripts/install-deps installs fonts-dejavu-core";
  const std::vector<ColourBar> bars = scene_colour_bars(overlay_scene());
  for (ColourBarPosition corner : {ColourBarPosition::top_left, ColourBarPosition::bottom_left,
                                   ColourBarPosition::bottom_right}) {
    Image image(512, 512, kBackground);
    const std::vector<ColourBarPlacement> placed =
        draw_colour_bars(image, bars, ColourBarStyle{corner});
    ASSERT_EQ(placed.size(), 2u) << colour_bar_position_name(corner);
    EXPECT_EQ(image.width(), 512);
    const bool left = corner != ColourBarPosition::bottom_right;
    const bool bottom = corner != ColourBarPosition::top_left;
    for (const ColourBarPlacement& p : placed) {
      EXPECT_EQ(p.x1 < 256, left) << colour_bar_position_name(corner);
      EXPECT_EQ(p.y0 > 256, bottom) << colour_bar_position_name(corner);
    }
    EXPECT_EQ(find_colour_bar_position(colour_bar_position_name(corner)), corner);
  }
  EXPECT_FALSE(find_colour_bar_position("middle"));
}

TEST(TextRaster, TextHasInkAndWidthGrowsWithIt) {
  ASSERT_TRUE(have_font())
      << "no font for colour bars: scripts/install-deps installs fonts-dejavu-core";
  const TextRaster text(find_font(), 14);
  const TextBitmap one = text.render("8"), three = text.render("888");
  EXPECT_GT(three.width, 2 * one.width);
  EXPECT_EQ(one.height, text.line_height());
  int ink = 0;
  for (uint8_t c : one.coverage) ink += c > 128;
  EXPECT_GT(ink, 10);
  EXPECT_GT(text.render("µ").width, 1);  // UTF-8
}

}  // namespace
}  // namespace imx
