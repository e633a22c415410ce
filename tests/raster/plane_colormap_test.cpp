// A plane's windowed value through its colour map, at the rasterizer where every method gets
// plane fragments.
#include <gtest/gtest.h>

#include <optional>

#include <glm/gtc/matrix_transform.hpp>

#include "core/colour.hpp"
#include "presets/colormap.hpp"
#include "raster/rasterizer.hpp"
#include "raster_test_util.hpp"

namespace imx {
namespace {

// An orthographic 16x16 view of a plane facing the camera through a volume of one value.
std::vector<Fragment> centre_fragments(float value, Colormap map, glm::dvec2 window,
                                       std::optional<double> threshold = std::nullopt,
                                       bool symmetric = false) {
  auto data = std::make_shared<VolumeData>();
  data->dims = {4, 4, 4};
  data->voxels = std::vector<float>(64, value);
  data->index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-3.0)) *
                         glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));
  Scene scene = test::make_scene(16, 16, Projection::orthographic);
  scene.camera.ortho_height = 4.0;
  VolumeObject vo;
  vo.name = "pet";
  vo.data = data;
  vo.index_to_world = data->index_to_world;
  vo.transfer_function.points = {{0.0, glm::vec4(0.0f)}};
  scene.volumes.push_back(vo);
  scene.order.push_back({ObjectKind::volume, 0});
  PlaneObject plane;
  plane.name = "overlay";
  plane.normal = {0, -1, 0};
  plane.up = {0, 0, 1};
  plane.size = {50, 50};
  plane.volume = 0;
  plane.window = window;
  plane.colormap = map;
  plane.color = {1.0f, 0.5f, 0.25f};
  plane.opacity = 0.8f;
  plane.threshold = threshold;
  plane.symmetric = symmetric;
  test::add_plane(scene, plane);
  std::vector<PreparedVolume> volumes;
  volumes.emplace_back(scene.volumes[0]);
  CameraModel camera(scene.camera, 16, 16);
  Rasterizer r(scene, camera, volumes, 16);
  test::FrameFragments f = test::rasterize_frame(r, camera, test::grid_offsets(1));
  return f.at(8, 8, 0);
}

Fragment centre_fragment(float value, Colormap map, glm::dvec2 window) {
  std::vector<Fragment> f = centre_fragments(value, map, window);
  EXPECT_EQ(f.size(), 1u);
  return f.empty() ? Fragment{} : f[0];
}

TEST(PlaneColormap, PixelIsTheMapsEntryTimesColourAndOpacity) {
  // Window [0, 255]: value 100 is t = 100/255, exactly entry 100 of a 256-entry table.
  for (Colormap map : {Colormap::hot, Colormap::inferno, Colormap::viridis}) {
    const detail::ColormapEntry& e = map == Colormap::hot       ? detail::kHot[100]
                                     : map == Colormap::inferno ? detail::kInferno[100]
                                                                : detail::kViridis[100];
    Fragment f = centre_fragment(100.0f, map, {127.5, 255.0});
    EXPECT_NEAR(f.color.r, e.r * 1.0f * 0.8f, 1e-5) << static_cast<int>(map);
    EXPECT_NEAR(f.color.g, e.g * 0.5f * 0.8f, 1e-5) << static_cast<int>(map);
    EXPECT_NEAR(f.color.b, e.b * 0.25f * 0.8f, 1e-5) << static_cast<int>(map);
    EXPECT_FLOAT_EQ(f.color.a, 0.8f);
  }
  // Below and above the window: the map's first and last entries.
  Fragment low = centre_fragment(-50.0f, Colormap::viridis, {127.5, 255.0});
  EXPECT_NEAR(low.color.b, detail::kViridis[0].b * 0.25f * 0.8f, 1e-6);
  Fragment high = centre_fragment(900.0f, Colormap::hot, {127.5, 255.0});
  EXPECT_NEAR(high.color.g, 1.0f * 0.5f * 0.8f, 1e-6);
}

// Grey is the same arithmetic as before colour maps: the same bytes.
// Grey is the windowed value's display grey (docs/colour.md), times the plane's colour.
TEST(PlaneColormap, GreyIsTheWindowedValuesDisplayGreyTimesColour) {
  Fragment f = centre_fragment(70.0f, Colormap::grey, {40.0, 100.0});
  const float grey =
      srgb_decode(std::clamp((70.0f - (40.0f - 0.5f * 100.0f)) / 100.0f, 0.0f, 1.0f));
  const glm::vec4 want(grey * 0.8f * glm::vec3(1.0f, 0.5f, 0.25f), 0.8f);
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(f.color[c], want[c], 1e-6f) << c;
}

// A threshold leaves no fragment below it (|value| below it when symmetric), so what lies behind
// the plane shows; at and above it the plane is drawn as without one.
TEST(PlaneColormap, ThresholdLeavesNoFragmentBelowIt) {
  const glm::dvec2 window{0.0, 16.0};
  EXPECT_TRUE(centre_fragments(2.9f, Colormap::hot, window, 3.0).empty());
  EXPECT_TRUE(centre_fragments(-5.0f, Colormap::hot, window, 3.0).empty());
  ASSERT_EQ(centre_fragments(3.0f, Colormap::hot, window, 3.0).size(), 1u);
  EXPECT_EQ(centre_fragments(5.0f, Colormap::hot, window, 3.0)[0].color,
            centre_fragment(5.0f, Colormap::hot, window).color);
  EXPECT_TRUE(centre_fragments(2.9f, Colormap::cold_hot, window, 3.0, true).empty());
  EXPECT_TRUE(centre_fragments(-2.9f, Colormap::cold_hot, window, 3.0, true).empty());
  ASSERT_EQ(centre_fragments(-3.0f, Colormap::cold_hot, window, 3.0, true).size(), 1u);
  EXPECT_EQ(centre_fragments(-6.0f, Colormap::cold_hot, window, 3.0, true)[0].color,
            centre_fragment(-6.0f, Colormap::cold_hot, window).color);
}

}  // namespace
}  // namespace imx
