// The reference converges on every example: more samples per pixel or a finer step change
// the image by less than the 40 dB the methods are judged at.
#include <gtest/gtest.h>

#include <filesystem>

#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

constexpr int kSize = 64;  // small images keep the suite fast; docs/ has the 512² numbers

class ReferenceConvergence : public testing::TestWithParam<std::string> {
 protected:
  Image render_example(int spp, double step_fraction) {
    std::filesystem::path file = std::filesystem::path(IMX_EXAMPLES_DIR) / (GetParam() + ".json");
    Scene scene = load_scene(
        file, {"image.width=" + std::to_string(kSize), "image.height=" + std::to_string(kSize)});
    scene.render.reference_step_fraction = step_fraction;
    RenderOptions options;
    options.method = "reference";
    options.spp = spp;
    return render(scene, options);
  }
};

TEST_P(ReferenceConvergence, SupersamplingAndStepHaveConverged) {
  Image base = render_example(16, 0.125);
  double spp_psnr = psnr(render_example(64, 0.125), base);
  EXPECT_GE(spp_psnr, 40.0) << "4x4 vs 8x8 samples per pixel";
  double step_psnr = psnr(render_example(16, 0.0625), base);
  EXPECT_GE(step_psnr, 40.0) << "step vs step/2";
  RecordProperty("psnr_spp_db", std::to_string(spp_psnr));
  RecordProperty("psnr_step_db", std::to_string(step_psnr));
}

INSTANTIATE_TEST_SUITE_P(Examples, ReferenceConvergence,
                         testing::Values("ct-head", "ct-implant", "two-volumes", "coplanar", "mpr",
                                         "shells", "fusion", "csg-cutaway", "csg-smile",
                                         "csg-sliced", "csg-mixing", "clip-head"),
                         [](const auto& info) {
                           std::string n = info.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

}  // namespace
}  // namespace imx
