// Translucent tubes inside a volume are intermixed exactly (issue 44): a real tract inside the
// MNI template, drawn translucent through a translucent DVR brain, scored in the band where the
// tubes meet the volume (the intersection-band metric, as for meshes).
// - The issue's criterion, at 256^2 with every default: zslab-hybrid at one sample per pixel
//   (its tube silhouettes covered, render.tube_coverage auto) scores at least 3 dB above mdvr
//   at one sample (drawn without) against the reference at 64 samples, and the reference has
//   converged (its 16 and 64 sample images agree to 40 dB).
// - Silhouette coverage on and off at 128^2 against 64 samples (StreamlineSilhouetteAa).
// - The intermixing alone, at 128^2: on the reference's own rays at one sample, coverage off
//   everywhere, zslab-hybrid at least 3 dB above mdvr. Both methods then end rays where the
//   reference does (its ERT, 0.999): at the default 0.99 every method drops up to 1% of the
//   light behind, a bias larger than the intermixing error, which mdvr's surfaces composited a
//   step early partly cancel (exact surface order, dfb, scores no better there). At the default
//   ERT zslab-hybrid must still not fall below mdvr.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/colour.hpp"
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
constexpr int kIssueSide = 256;  // the issue's image size
constexpr double kFovDeg = 26.0;

// `ert`: render.ert_threshold, empty for the default; `brain_visible` false hides the volume;
// `coverage`: render.tube_coverage, empty for the default.
Scene tract_in_brain(const std::string& method, int spp, std::optional<double> ert = {},
                     bool brain_visible = true, const std::string& coverage = "", int side = kSide,
                     double fov_deg = kFovDeg) {
  // The brain faintly opaque (half its light gone about 20 mm in), so the tract, 1 mm thick
  // and a third opaque per crossing, passes in and out of the depth where the brain reaches 0.5.
  // Its colours are the linear ones the measure was made with, given as the display colours
  // that decode to them (docs/colour.md), so that the scene renders as it did.
  const auto d = [](float linear) { return srgb_encode_exact(linear); };
  const nlohmann::json scene = {
      {"camera",
       {{"eye", {-400, -60, 120}},
        {"target", {0, -18, 8}},
        {"up", {0, 0, 1}},
        {"fov_deg", fov_deg}}},
      {"image", {{"width", side}, {"height", side}, {"background", {0, 0, 0, 1}}}},
      {"render", {{"method", method}, {"spp", spp}}},
      {"objects",
       {{{"name", "t1"},
         {"type", "volume"},
         {"visible", brain_visible},
         {"source", {{"file", test::shared_data(kTemplate).string()}}},
         {"transfer_function",
          {{"points",
            {{0, 0, 0, 0, 0},
             {40, d(0.6f), d(0.5f), d(0.4f), 0},
             {90, d(0.9f), d(0.8f), d(0.7f), 0.02},
             {255, 1, 1, 1, 0.05}}}}}},
        {{"name", "ifof"},
         {"type", "streamlines"},
         {"radius", 1.0},
         {"opacity", 0.35},
         {"source", {{"file", test::shared_data(kTract).string()}}}}}}};
  Scene parsed = parse_scene(scene.dump(), ".", "test");
  if (ert) parsed.render.ert_threshold = *ert;
  if (!coverage.empty()) parsed.render.tube_coverage = coverage;
  return parsed;
}

// The band where the tract crosses the brain's half-opacity depth, at least `least` pixels.
std::vector<uint8_t> tube_volume_band(const Scene& scene, size_t least, size_t& pixels) {
  std::vector<uint8_t> band =
      intersection_band(first_hit_depth(scene, "t1", 0.5f), first_hit_depth(scene, "ifof"), 2);
  pixels = 0;
  for (uint8_t b : band) pixels += b;
  EXPECT_GT(pixels, least) << "the tract must cross the brain's half-opacity depth on screen";
  return band;
}

// The issue's criterion on the central `side` x `side` pixels of the 256^2 image: the same
// rays, the field of view narrowed so that its edges fall on those pixels' edges.
void issue_criterion(int side) {
  const double half = kFovDeg * std::numbers::pi / 360.0;
  const double fov = std::atan(std::tan(half) * side / kIssueSide) * 360.0 / std::numbers::pi;
  auto scene = [&](const std::string& method, int spp, std::optional<double> ert = {}) {
    return tract_in_brain(method, spp, ert, true, "", side, fov);
  };
  const Image ref64 = render(scene("reference", 64));
  const Image ref16 = render(scene("reference", 16));
  const Image zslab = render(scene("zslab-hybrid", 1));
  const Image mdvr = render(scene("mdvr", 1));
  size_t in_band = 0;
  const std::vector<uint8_t> band = tube_volume_band(scene("reference", 1), 150, in_band);
  const double converged = psnr(ref16, ref64);
  const double zslab_db = masked_psnr(zslab, ref64, band);
  const double mdvr_db = masked_psnr(mdvr, ref64, band);
  // Recorded only: both at the reference's ERT, as the same-ray test below.
  const double reference_ert = ReferenceParams{}.ert;
  const double zslab_ert =
      masked_psnr(render(scene("zslab-hybrid", 1, reference_ert)), ref64, band);
  const double mdvr_ert = masked_psnr(render(scene("mdvr", 1, reference_ert)), ref64, band);
  using ::testing::Test;
  Test::RecordProperty("band_pixels", static_cast<int>(in_band));
  Test::RecordProperty("reference_16_vs_64_db", fmt::format("{:.2f}", converged));
  Test::RecordProperty("band_db_vs_64spp",
                       fmt::format("zslab-hybrid {:.2f}, mdvr {:.2f}", zslab_db, mdvr_db));
  Test::RecordProperty("band_db_vs_64spp_reference_ert",
                       fmt::format("zslab-hybrid {:.2f}, mdvr {:.2f}", zslab_ert, mdvr_ert));
  EXPECT_GE(converged, 40.0);
  EXPECT_GE(zslab_db, mdvr_db + 3.0) << "zslab-hybrid " << zslab_db << " dB, mdvr " << mdvr_db
                                     << " dB in " << in_band << " band pixels";
}

// The central 128^2 of the 256^2 image, where the tract crosses the brain most: the whole
// image's 64-sample reference takes about three minutes on two shared cores.
TEST(StreamlineExactness, AtTheIssueSizeZslabHybridBeatsMdvrAgainstSixtyFourSamples) {
  SKIP_WITHOUT_SHARED_DATA(kTract, kTemplate);
#ifdef IMX_SANITIZED
  GTEST_SKIP() << "the reference at 64 samples per pixel, only in the release build";
#endif
  issue_criterion(kIssueSide / 2);
}

// The whole 256^2 image, run by hand (--gtest_also_run_disabled_tests); its numbers are in
// docs/streamlines.md.
TEST(StreamlineExactness, DISABLED_WholeImageAtTheIssueSize) {
  SKIP_WITHOUT_SHARED_DATA(kTract, kTemplate);
  issue_criterion(kIssueSide);
}

TEST(StreamlineExactness, ZslabHybridBeatsMdvrWhereTubesMeetTheVolumeOnTheSameRays) {
  SKIP_WITHOUT_SHARED_DATA(kTract, kTemplate);
  // The reference at one sample draws no coverage: neither do the methods, on the same rays.
  const Image ref1 = render(tract_in_brain("reference", 1));
  const double reference_ert = ReferenceParams{}.ert;
  const Image zslab = render(tract_in_brain("zslab-hybrid", 1, reference_ert, true, "off"));
  const Image mdvr = render(tract_in_brain("mdvr", 1, reference_ert, true, "off"));
  const Image zslab_default = render(tract_in_brain("zslab-hybrid", 1, {}, true, "off"));
  const Image mdvr_default = render(tract_in_brain("mdvr", 1, {}, true, "off"));
  size_t in_band = 0;
  const std::vector<uint8_t> band = tube_volume_band(tract_in_brain("reference", 1), 80, in_band);
  if (in_band <= 80) return;

  const double zslab_same_rays = masked_psnr(zslab, ref1, band);
  const double mdvr_same_rays = masked_psnr(mdvr, ref1, band);
  const double zslab_default_ert = masked_psnr(zslab_default, ref1, band);
  const double mdvr_default_ert = masked_psnr(mdvr_default, ref1, band);
  RecordProperty("band_pixels", static_cast<int>(in_band));
  RecordProperty("band_db_vs_1spp",
                 fmt::format("zslab-hybrid {:.2f}, mdvr {:.2f}", zslab_same_rays, mdvr_same_rays));
  RecordProperty("band_db_vs_1spp_default_ert", fmt::format("zslab-hybrid {:.2f}, mdvr {:.2f}",
                                                            zslab_default_ert, mdvr_default_ert));
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
// on the same rays (coverage off, as the reference at one sample). Before, only the first L = 4
// crossings showed (26 dB on the tract).
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
    const double db = masked_psnr(render(tract_in_brain(method, 1, {}, false, "off")), ref1, tract);
    RecordProperty(fmt::format("tract_db_{}", method), fmt::format("{:.2f}", db));
    EXPECT_GE(db, 60.0) << method;
  }
}

// Silhouette coverage (render.tube_coverage) on the same scene: each 1-sample method, coverage
// off and on, against the 64-sample reference drawn without it, in the band and the whole
// image, at the reference's ERT. Recorded, and coverage must not lose.
TEST(StreamlineSilhouetteAa, CoverageBringsOneSampleCloserToSixtyFour) {
  SKIP_WITHOUT_SHARED_DATA(kTract, kTemplate);
#ifdef IMX_SANITIZED
  GTEST_SKIP() << "the reference at 64 samples per pixel, only in the release build";
#endif
  const double ert = ReferenceParams{}.ert;
  const Image ref64 = render(tract_in_brain("reference", 64, ert));
  const Scene scene = tract_in_brain("reference", 1, ert);
  const std::vector<uint8_t> band =
      intersection_band(first_hit_depth(scene, "t1", 0.5f), first_hit_depth(scene, "ifof"), 2);
  for (const char* method : {"zslab-hybrid", "mdvr", "zslab"}) {
    const Image off = render(tract_in_brain(method, 1, ert, true, "off"));
    const Image on = render(tract_in_brain(method, 1, ert, true, "on"));
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
