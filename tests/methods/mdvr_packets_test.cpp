// mdvr with render.packets (one volume marched 8 rays at a time) against one ray at a time.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/renderer.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

Image render_mdvr(Scene scene, bool packets) {
  scene.render.packets = packets;
  RenderOptions o;
  o.method = "mdvr";
  return render(scene, o);
}

// Float reassociation only: far above what 8-bit output can show.
TEST(MdvrPackets, SameImageAsOneRayAtATime) {
  for (const std::string& extra :
       {std::string("render.skipping=distance"), std::string("render.gradients=on-the-fly"),
        std::string("render.ert_threshold=0.6")}) {
    Scene s = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "ct-head.json",
                         {"image.width=61", "image.height=47", "objects.ct.source.size=64", extra});
    EXPECT_GE(psnr(render_mdvr(s, false), render_mdvr(s, true)), 70.0) << extra;
  }
}

}  // namespace
}  // namespace imx
