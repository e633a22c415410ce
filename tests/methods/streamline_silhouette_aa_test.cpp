// Silhouette coverage of tubes at one sample per pixel (issue 44), measured where the tract of
// streamline_exactness_test meets the brain: the 1-sample methods against the 64-sample
// reference in the intersection band, with coverage off and on (render.tube_coverage). The
// reference is drawn without it. Recorded, and coverage must not lose.
#include <gtest/gtest.h>

#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "intermix/band_metrics.hpp"
#include "intermix/io.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "methods/reference/reference_kernel.hpp"
#include "probes/first_hit_depth.hpp"
#include "shared_data.hpp"

namespace imx {
namespace {

constexpr const char* kTract = "neuro/tracts/tract.IFOF_R.trk";
constexpr const char* kTemplate = "neuro/volumes/avg152T1_RL_nifti.nii.gz";
constexpr int kSide = 128;

// streamline_exactness_test's scene, with the reference's ERT.
Scene tract_in_brain(const std::string& method, int spp) {
  const nlohmann::json scene = {
      {"camera",
       {{"eye", {-400, -60, 120}}, {"target", {0, -18, 8}}, {"up", {0, 0, 1}}, {"fov_deg", 26}}},
      {"image", {{"width", kSide}, {"height", kSide}, {"background", {0, 0, 0, 1}}}},
      {"render", {{"method", method}, {"spp", spp}}},
      {"objects",
       {{{"name", "t1"},
         {"type", "volume"},
         {"source", {{"file", test::shared_data(kTemplate).string()}}},
         {"transfer_function",
          {{"points",
            {{0, 0, 0, 0, 0},
             {40, 0.6, 0.5, 0.4, 0},
             {90, 0.9, 0.8, 0.7, 0.02},
             {255, 1, 1, 1, 0.05}}}}}},
        {{"name", "ifof"},
         {"type", "streamlines"},
         {"radius", 1.0},
         {"opacity", 0.35},
         {"source", {{"file", test::shared_data(kTract).string()}}}}}}};
  Scene parsed = parse_scene(scene.dump(), ".", "test");
  parsed.render.ert_threshold = ReferenceParams{}.ert;
  return parsed;
}

Image render_with_coverage(const std::string& method, bool coverage) {
  Scene scene = tract_in_brain(method, 1);
  scene.render.tube_coverage = coverage ? "on" : "off";
  return render(scene);
}

TEST(StreamlineSilhouetteAa, CoverageBringsOneSampleCloserToSixtyFour) {
  SKIP_WITHOUT_SHARED_DATA(kTract, kTemplate);
#ifdef IMX_SANITIZED
  GTEST_SKIP() << "the reference at 64 samples per pixel, only in the release build";
#endif
  const Image ref64 = render(tract_in_brain("reference", 64));
  const Scene scene = tract_in_brain("reference", 1);
  const std::vector<uint8_t> band =
      intersection_band(first_hit_depth(scene, "t1", 0.5f), first_hit_depth(scene, "ifof"), 2);
  std::vector<uint8_t> everywhere(band.size(), 1);
  for (const char* method : {"zslab-hybrid", "mdvr", "zslab"}) {
    const Image off = render_with_coverage(method, false), on = render_with_coverage(method, true);
    const double band_off = masked_psnr(off, ref64, band), band_on = masked_psnr(on, ref64, band);
    const double all_off = psnr(off, ref64), all_on = psnr(on, ref64);
    RecordProperty(fmt::format("band_db_vs_64spp_{}", method),
                   fmt::format("off {:.2f}, on {:.2f}", band_off, band_on));
    RecordProperty(fmt::format("image_db_vs_64spp_{}", method),
                   fmt::format("off {:.2f}, on {:.2f}", all_off, all_on));
    EXPECT_GT(band_on, band_off) << method;
    EXPECT_GT(all_on, all_off) << method;
  }
}

}  // namespace
}  // namespace imx
