// The multi-fragment methods on example scenes at 64x64, judged against dfb (the multi-fragment
// ground truth); docs/multi_fragment.md has the 512x512 numbers.
#include <gtest/gtest.h>

#include <filesystem>

#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "probes/z_fighting_probe.hpp"

namespace imx {
namespace {

Scene example(const std::string& name, std::vector<std::string> overrides = {}) {
  overrides.push_back("image.width=64");
  overrides.push_back("image.height=64");
  return load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / (name + ".json"), overrides);
}

Image render_with(const Scene& scene, const std::string& method) {
  RenderOptions options;
  options.method = method;
  return render(scene, options);
}

TEST(MultiFragmentRender, EveryMethodIsCloseToDfbOnShells) {
  Scene scene = example("shells", {"render.k=16", "render.peel_layers=16"});
  Image truth = render_with(scene, "dfb");
  // shells has up to 20 separate layers: with 16 slots the bounded methods are nearly exact
  const std::pair<const char*, double> floors[] = {{"dfb-sfm", 60.0},     {"kbuffer", 50.0},
                                                   {"kbuffer-ofm", 50.0}, {"peel", 40.0},
                                                   {"wboit", 25.0},       {"mboit", 40.0}};
  for (const auto& [method, floor] : floors)
    EXPECT_GE(psnr(render_with(scene, method), truth), floor) << method;
}

TEST(MultiFragmentRender, OfmBeatsThePlainKBufferOnTheManyLayerScene) {
  Scene scene = example("torus-planes", {"render.k=4"});
  Image truth = render_with(scene, "dfb");
  double plain = psnr(render_with(scene, "kbuffer"), truth);
  double ofm = psnr(render_with(scene, "kbuffer-ofm"), truth);
  EXPECT_GE(ofm, plain + 2.0) << "kbuffer " << plain << " dB, kbuffer-ofm " << ofm << " dB";
}

TEST(MultiFragmentRender, MergingRemovesZFightingOfTiltedCoplanarQuads) {
  // zoomed in, so the coplanar region covers a good part of the small image
  Scene scene = example("coplanar-tilted", {"camera.fov_deg=12"});
  auto measure = [&](const char* method) {
    RenderOptions options;
    options.method = method;
    return measure_z_fighting(scene, options);
  };
  ZFightingStats dfb = measure("dfb");
  EXPECT_GT(dfb.pixels, 100);
  EXPECT_GT(dfb.speckle, 2.0 / 255.0);
  EXPECT_GT(dfb.jitter_change, 2.0 / 255.0);
  for (const char* method : {"dfb-sfm", "kbuffer-ofm", "wboit", "mboit"}) {
    ZFightingStats s = measure(method);
    EXPECT_LT(s.std_dev, 1.0 / 255.0) << method;
    EXPECT_LT(s.jitter_change, 0.5 / 255.0) << method;
  }
}

TEST(MultiFragmentRender, PeelAndDfbSfmFollowTheReferenceWithAVolume) {
  Scene scene = example("ct-implant", {"objects.ct.source.size=64"});
  RenderOptions options;
  options.method = "reference";
  options.spp = 4;
  Image ref = render(scene, options);
  for (const char* method : {"dfb", "dfb-sfm", "peel", "kbuffer-ofm"}) {
    options.method = method;
    EXPECT_GE(psnr(render(scene, options), ref), 35.0) << method;
  }
}

}  // namespace
}  // namespace imx
