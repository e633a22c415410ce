// FrameSetup's per-pixel volume mask: which volumes every per-sample method marches in a pixel.
#include "frame/frame_setup.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "intermix/scene.hpp"
#include "marcher_finds.hpp"
#include "volume/ray_volumes.hpp"

namespace imx {
namespace {

// A wide and a tall image, so that swapping x and y would leave out the wrong pixels; the target
// off centre, so that many rays meet a volume's box but none of its occupied bricks.
TEST(FrameSetup, VolumesMayShowLeavesOutOnlyRaysWithNothingToMarch) {
  for (const char* size : {"image.width=64", "image.height=64"}) {
    const Scene s = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "two-volumes.json",
                               {"image.width=40", "image.height=40", size});
    FrameSetup frame(s);
    ASSERT_EQ(frame.volumes.size(), 2u);
    EXPECT_EQ(frame.volumes_may_show(0, 0), kEveryVolume) << "nothing is known before accelerate";
    const float step = static_cast<float>(frame.min_pitch);
    frame.accelerate(step, MarchSettings::from(s.render));
    int left_out = 0, marched = 0;
    for (int y = 0; y < s.image.height; ++y)
      for (int x = 0; x < s.image.width; ++x) {
        const Ray ray = frame.camera.ray(x + 0.5, y + 0.5);
        const VolumeMask mask = frame.volumes_may_show(x, y);
        const RayVolumes all(ray, frame.volumes, step, 4, frame.lights);
        const RayVolumes masked(ray, frame.volumes, step, 4, frame.lights, mask);
        for (size_t v = 0; v < 2; ++v) {
          const bool may_show = (mask >> v & 1u) != 0;
          EXPECT_EQ(masked.marched[v], all.marched[v] && may_show) << x << ", " << y;
          if (test::marcher_finds_something(frame.volumes[v], ray, step, frame.lights)) {
            EXPECT_TRUE(may_show) << size << " volume " << v << " pixel " << x << ", " << y;
            ++marched;
          } else if (all.marched[v] && !may_show) {
            ++left_out;
          }
        }
      }
    EXPECT_GT(marched, 300) << size;
    EXPECT_GT(left_out, 100) << size;  // rays that meet a box and would have walked it
  }
}

}  // namespace
}  // namespace imx
