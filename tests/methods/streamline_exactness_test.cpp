// Translucent tubes inside a volume are intermixed exactly (issue 44): a real tract inside the
// MNI template, drawn translucent through a translucent DVR brain. In the band where the tubes
// meet the volume (the intersection-band metric, as for meshes), zslab-hybrid at one sample per
// pixel scores at least 3 dB above mdvr against the reference on the same rays (one sample: the
// intermixing alone, as docs/zslab.md measures meshes), and the reference has converged (its 16
// and 64 sample images agree to 40 dB). Both methods then end rays where the reference does
// (its ERT, 0.999): at the default 0.99 every method drops up to 1% of the light behind, a bias
// larger than the intermixing error, which mdvr's surfaces composited a step early partly cancel
// (exact surface order, dfb, scores no better there). At the default ERT zslab-hybrid must still
// not fall below mdvr. Against the 64-sample reference both 1-sample methods are dominated by
// the tubes' aliased silhouettes: recorded, and in docs/streamlines.md.
// At 128^2 (the 64-sample reference is most of the test's time).
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
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

// `ert`: render.ert_threshold, empty for the default; `brain_visible` false hides the volume.
Scene tract_in_brain(const std::string& method, int spp, std::optional<double> ert = {},
                     bool brain_visible = true) {
  // The brain faintly opaque (half its light gone about 20 mm in), so the tract, 1 mm thick
  // and a third opaque per crossing, passes in and out of the depth where the brain reaches 0.5.
  const nlohmann::json scene = {
      {"camera",
       {{"eye", {-400, -60, 120}}, {"target", {0, -18, 8}}, {"up", {0, 0, 1}}, {"fov_deg", 26}}},
      {"image", {{"width", kSide}, {"height", kSide}, {"background", {0, 0, 0, 1}}}},
      {"render", {{"method", method}, {"spp", spp}}},
      {"objects",
       {{{"name", "t1"},
         {"type", "volume"},
         {"visible", brain_visible},
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
  if (ert) parsed.render.ert_threshold = *ert;
  return parsed;
}

TEST(StreamlineExactness, ZslabHybridBeatsMdvrWhereTubesMeetTheVolume) {
  SKIP_WITHOUT_SHARED_DATA(kTract, kTemplate);
#ifdef IMX_SANITIZED
  GTEST_SKIP() << "the reference at 64 samples per pixel, as ReferenceConvergence, only in the "
                  "release build";
#endif
  const Image ref64 = render(tract_in_brain("reference", 64));
  const Image ref16 = render(tract_in_brain("reference", 16));
  const Image ref1 = render(tract_in_brain("reference", 1));
  const double reference_ert = ReferenceParams{}.ert;
  const Image zslab = render(tract_in_brain("zslab-hybrid", 1, reference_ert));
  const Image mdvr = render(tract_in_brain("mdvr", 1, reference_ert));
  const Image zslab_default = render(tract_in_brain("zslab-hybrid", 1));
  const Image mdvr_default = render(tract_in_brain("mdvr", 1));
  const Scene scene = tract_in_brain("reference", 1);
  const std::vector<uint8_t> band =
      intersection_band(first_hit_depth(scene, "t1", 0.5f), first_hit_depth(scene, "ifof"), 2);
  size_t in_band = 0;
  for (uint8_t b : band) in_band += b;
  ASSERT_GT(in_band, 80u) << "the tract must cross the brain's half-opacity depth on screen";

  const double converged = psnr(ref16, ref64);
  const double zslab_same_rays = masked_psnr(zslab, ref1, band);
  const double mdvr_same_rays = masked_psnr(mdvr, ref1, band);
  const double zslab_default_ert = masked_psnr(zslab_default, ref1, band);
  const double mdvr_default_ert = masked_psnr(mdvr_default, ref1, band);
  RecordProperty("band_pixels", static_cast<int>(in_band));
  RecordProperty("reference_16_vs_64_db", fmt::format("{:.2f}", converged));
  RecordProperty("band_db_vs_1spp",
                 fmt::format("zslab-hybrid {:.2f}, mdvr {:.2f}", zslab_same_rays, mdvr_same_rays));
  RecordProperty("band_db_vs_1spp_default_ert", fmt::format("zslab-hybrid {:.2f}, mdvr {:.2f}",
                                                            zslab_default_ert, mdvr_default_ert));
  RecordProperty("band_db_vs_64spp",
                 fmt::format("zslab-hybrid {:.2f}, mdvr {:.2f}", masked_psnr(zslab, ref64, band),
                             masked_psnr(mdvr, ref64, band)));
  EXPECT_GE(converged, 40.0);
  EXPECT_GE(zslab_same_rays, mdvr_same_rays + 3.0)
      << "zslab-hybrid " << zslab_same_rays << " dB, mdvr " << mdvr_same_rays << " dB in "
      << in_band << " band pixels";
  EXPECT_GE(zslab_default_ert, mdvr_default_ert)
      << "at the default ERT: zslab-hybrid " << zslab_default_ert << " dB, mdvr "
      << mdvr_default_ert << " dB";
}

// Rays crossing many translucent tubes: the zSlab pipelines draw every crossing that can show
// (tubes are ray-traced, not peeled to L layers) in exact order (no virtual thickness mixing a
// tube's entry with its exit), so with the brain hidden they draw the tract as the reference does
// on the same rays. Before, only the first L = 4 crossings showed (26 dB on the tract).
TEST(StreamlineExactness, ZslabDrawsEveryTranslucentCrossingInOrder) {
  SKIP_WITHOUT_SHARED_DATA(kTract, kTemplate);
  const Scene scene = tract_in_brain("reference", 1, {}, false);
  const Image ref1 = render(scene);
  const Image depth = first_hit_depth(scene, "ifof");
  std::vector<uint8_t> tract(depth.size(), 0);
  size_t tract_pixels = 0;
  for (size_t i = 0; i < depth.size(); ++i) {
    tract[i] = std::isfinite(depth.data()[i].r) ? 1 : 0;
    tract_pixels += tract[i];
  }
  ASSERT_GT(tract_pixels, 500u);
  for (const char* method : {"zslab-hybrid", "zslab"}) {
    const double db = masked_psnr(render(tract_in_brain(method, 1, {}, false)), ref1, tract);
    RecordProperty(fmt::format("tract_db_{}", method), fmt::format("{:.2f}", db));
    EXPECT_GE(db, 60.0) << method;
  }
}

}  // namespace
}  // namespace imx
