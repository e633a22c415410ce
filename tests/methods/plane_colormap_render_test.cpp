// Every method shows a plane's colour map the same way: plane fragments all come from the
// rasterizer, so each method's pixel is the map's colour.
#include <gtest/gtest.h>

#include "homogeneous_volume.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "presets/colormap.hpp"

namespace imx {
namespace {

TEST(PlaneColormapRender, EveryMethodShowsTheMapsColour) {
  Scene scene;
  scene.image.width = 8;
  scene.image.height = 8;
  scene.camera.projection = Projection::orthographic;
  scene.camera.ortho_height = 10.0;
  scene.volumes.push_back(test::homogeneous_volume(0.0f, glm::vec3(1.0f)));  // invisible, value 1
  scene.order.push_back({ObjectKind::volume, 0});
  PlaneObject plane;
  plane.name = "pet";
  plane.normal = {0, -1, 0};
  plane.up = {0, 0, 1};
  plane.size = {40, 40};
  plane.volume = 0;
  plane.window = {0.5, 2.0};  // value 1 is t = 0.75
  plane.colormap = Colormap::viridis;
  scene.planes.push_back(plane);
  scene.order.push_back({ObjectKind::plane, 0});
  const glm::vec3 want = colormap_rgb(Colormap::viridis, 0.75f);
  for (const char* method : {"reference", "mdvr", "peel", "dfb", "dfb-sfm", "kbuffer",
                             "kbuffer-ofm", "wboit", "mboit", "zslab", "zslab-hybrid"}) {
    RenderOptions options;
    options.method = method;
    options.threads = 1;
    const Image image = render(scene, options);
    const glm::vec4 got = image.at(4, 4);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 2e-3) << method << " channel " << c;
    EXPECT_NEAR(got.a, 1.0f, 1e-4) << method;
  }
}

}  // namespace
}  // namespace imx
