// Progressive refinement and cancellation (RenderOptions::sample_index, ::cancel), what the
// viewer builds on: the mean of the spp one-sample frames is the spp frame, in every method
// that takes a sample pattern; a set cancel flag stops render() with imx::Cancelled.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <string>

#include "intermix/error.hpp"
#include "intermix/render.hpp"
#include "intermix/renderer.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

constexpr int kSize = 32;

Scene example(const std::string& name) {
  return load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / name,
                    {"image.width=" + std::to_string(kSize),
                     "image.height=" + std::to_string(kSize), "objects.ct.source.size=48"});
}

double max_difference(const Image& a, const Image& b) {
  double worst = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 4; ++c)
      worst = std::max(worst, static_cast<double>(std::abs(a.data()[i][c] - b.data()[i][c])));
  return worst;
}

class Progressive : public ::testing::TestWithParam<const char*> {};

TEST_P(Progressive, MeanOfOneSampleFramesIsTheSppFrame) {
  const Scene scene = example("ct-implant.json");
  constexpr int kSpp = 4;
  RenderOptions options;
  options.method = GetParam();
  options.spp = kSpp;
  const Image whole = render(scene, options);
  Image sum(kSize, kSize);
  Image first;
  for (int k = 0; k < kSpp; ++k) {
    options.sample_index = k;
    const Image one = render(scene, options);
    if (k == 0) first = one;
    for (size_t i = 0; i < sum.size(); ++i) sum.data()[i] += one.data()[i];
  }
  for (size_t i = 0; i < sum.size(); ++i) sum.data()[i] *= 1.0f / kSpp;
  EXPECT_LT(max_difference(sum, whole), 1e-5);
  // One sample alone is not the whole frame: the jitter is real.
  EXPECT_GT(max_difference(first, whole), 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Methods, Progressive,
                         ::testing::Values("reference", "mdvr", "dfb", "peel", "zslab",
                                           "zslab-hybrid"));

TEST(Progressive, SampleIndexOutsideThePatternIsRefused) {
  const Scene scene = example("ct-implant.json");
  RenderOptions options;
  options.method = "zslab";
  options.spp = 4;
  options.sample_index = 4;
  try {
    render(scene, options);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("sample_index: 4"), std::string::npos) << e.what();
  }
}

TEST(Cancel, ASetFlagStopsEveryMethodAtOnce) {
  const Scene scene = example("ct-implant.json");
  const std::atomic<bool> cancel{true};
  for (const char* method : {"reference", "mdvr", "zslab", "dfb"}) {
    RenderOptions options;
    options.method = method;
    options.cancel = &cancel;
    EXPECT_THROW(render(scene, options), Cancelled) << method;
  }
}

TEST(Cancel, AFlagSetMidFrameStopsIt) {
  const Scene scene = example("ct-implant.json");
  std::atomic<bool> cancel{false};
  int reports_after_cancel = 0;
  RenderOptions options;
  options.method = "zslab";
  options.cancel = &cancel;
  options.threads = 1;
  // The first progress report sets the flag, as a viewer's new input would.
  options.progress = [&](double) {
    if (cancel) ++reports_after_cancel;
    cancel = true;
  };
  Renderer renderer;
  EXPECT_THROW(renderer.render(scene, options), Cancelled);
  EXPECT_EQ(reports_after_cancel, 0);
  // The renderer is whole after a cancelled frame: the next one equals a fresh render.
  cancel = false;
  options.progress = nullptr;
  const Image after = renderer.render(scene, options);
  RenderOptions plain;
  plain.method = "zslab";
  EXPECT_EQ(max_difference(after, render(scene, plain)), 0.0);
}

}  // namespace
}  // namespace imx
