// NaN and infinite voxels are "no data" (issue 31): every method and style renders a map that
// has them like the same map with those voxels replaced by a value the transfer function hides.
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "intermix/error.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

constexpr int kSize = 32;      // voxels a side, 1 mm apart, centred on the origin
constexpr float kRadius = 12;  // the blob's radius in voxels
constexpr int kImage = 48;     // pixels a side
constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// What lies outside the blob: one value, or NaN, +inf and -inf in turn (`mixed`).
struct Outside {
  float value = 0.0f;
  bool mixed = false;
  std::string name;
};

// A statistical-map-like blob: inside the sphere 100 (1 - r / R) (a peak at the centre, 0 at
// the rim) or, `rising`, 100 r / R (a dip at the centre, 100 at the rim); outside, `outside`.
std::shared_ptr<const VolumeData> blob(bool rising, const Outside& outside) {
  auto data = std::make_shared<VolumeData>();
  data->dims = glm::ivec3(kSize);
  data->index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-0.5 * (kSize - 1)));
  std::vector<float> v(static_cast<size_t>(kSize) * kSize * kSize);
  const float c = 0.5f * (kSize - 1);
  const float cycle[3] = {kNan, kInf, -kInf};
  size_t n = 0;
  for (int k = 0; k < kSize; ++k)
    for (int j = 0; j < kSize; ++j)
      for (int i = 0; i < kSize; ++i, ++n) {
        // Slightly off-centre, so that the blob is not symmetric about the voxel grid.
        const float r = glm::length(glm::vec3(i, j, k) - glm::vec3(c + 0.7f, c - 0.4f, c + 0.3f));
        if (r <= kRadius)
          v[n] = rising ? 100.0f * r / kRadius : 100.0f * (1.0f - r / kRadius);
        else
          v[n] = outside.mixed ? cycle[n % 3] : outside.value;
      }
  data->voxels = std::move(v);
  return data;
}

// What a style needs of its TF and of the replacement value so that the replaced map is a
// correct reference: the replacement must be a value the TF hides and that never wins.
struct StyleCase {
  const char* name;
  VolumeStyle style;
  XrayMode xray = XrayMode::integral;
  bool rising = false;      // the blob's profile
  float replacement = 0.0;  // hidden by the TF, never the max (MIP) or min (MinIP)
  TransferFunction tf;
  bool shading = false;
};

std::vector<StyleCase> style_cases() {
  std::vector<StyleCase> cases;
  TransferFunction dvr;
  dvr.points = {{0.0, glm::vec4(0.0f)},
                {20.0, glm::vec4(0.9f, 0.6f, 0.3f, 0.0f)},
                {60.0, glm::vec4(1.0f, 0.8f, 0.5f, 0.08f)},
                {100.0, glm::vec4(1.0f, 1.0f, 0.9f, 0.5f)}};
  cases.push_back({"dvr", VolumeStyle::dvr, XrayMode::integral, false, 0.0f, dvr, true});
  cases.push_back({"dvr-unlit", VolumeStyle::dvr, XrayMode::integral, false, 0.0f, dvr, false});
  TransferFunction iso;
  iso.points = {{0.0, glm::vec4(0.9f, 0.7f, 0.5f, 1.0f)}};
  cases.push_back({"iso", VolumeStyle::iso, XrayMode::integral, false, 0.0f, iso, true});
  TransferFunction mip;
  mip.points = {{10.0, glm::vec4(0.0f)}, {100.0, glm::vec4(1.0f, 0.9f, 0.8f, 1.0f)}};
  cases.push_back({"mip", VolumeStyle::mip, XrayMode::integral, false, 0.0f, mip});
  // MinIP of the dip: visible below 90, hidden above, where the replacement (200) lies.
  TransferFunction minip;
  minip.points = {{0.0, glm::vec4(1.0f, 0.9f, 0.8f, 1.0f)}, {90.0, glm::vec4(0.0f)}};
  cases.push_back({"minip", VolumeStyle::minip, XrayMode::integral, true, 200.0f, minip});
  // X-ray integrates the TF's attenuation: 0 below 10, so the replacement 0 adds nothing.
  TransferFunction xray;
  xray.points = {{10.0, glm::vec4(0.0f)}, {100.0, glm::vec4(1.0f, 1.0f, 1.0f, 0.06f)}};
  cases.push_back({"xray", VolumeStyle::xray, XrayMode::integral, false, 0.0f, xray});
  return cases;
}

Scene blob_scene(const StyleCase& s, std::shared_ptr<const VolumeData> data) {
  VolumeObject v;
  v.name = "map";
  v.data = std::move(data);
  v.index_to_world = v.data->index_to_world;
  v.transfer_function = s.tf;
  v.style = s.style;
  v.xray_mode = s.xray;
  v.iso_value = 50.0;
  v.shading.enabled = s.shading;
  Scene scene;
  scene.camera.eye = {18.0, -80.0, 30.0};
  scene.camera.target = {0.0, 0.0, 0.0};
  scene.camera.up = {0.0, 0.0, 1.0};
  scene.camera.fov_deg = 30.0;
  scene.image.width = scene.image.height = kImage;
  scene.volumes.push_back(v);
  scene.order.push_back({ObjectKind::volume, 0});
  return scene;
}

int non_finite_pixels(const Image& image) {
  int bad = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    const glm::vec4& p = image.data()[i];
    bad += !(std::isfinite(p.r) && std::isfinite(p.g) && std::isfinite(p.b) && std::isfinite(p.a));
  }
  return bad;
}

Image render_with(const Scene& scene, const std::string& method) {
  RenderOptions options;
  options.method = method;
  options.spp = 1;
  options.threads = 1;
  return render(scene, options);
}

std::vector<Outside> no_data_kinds() {
  return {{kNan, false, "nan"}, {kInf, false, "+inf"}, {-kInf, false, "-inf"}, {0, true, "mixed"}};
}

// Every method and style: the map with no data renders as the map with a hidden value there,
// judged by the reference of the latter, within 1 dB of what the method gives on the latter.
TEST(NoDataRender, EveryMethodAndStyleTreatsNanAndInfAsAHiddenValue) {
  const std::vector<std::string> methods = available_methods();
  double worst_margin = INFINITY, worst_direct = INFINITY;
  for (const StyleCase& s : style_cases()) {
    const Scene replaced = blob_scene(s, blob(s.rising, {s.replacement, false, "value"}));
    const Image truth = render_with(replaced, "reference");
    for (const Outside& kind : no_data_kinds()) {
      const Scene missing = blob_scene(s, blob(s.rising, kind));
      for (const std::string& method : methods) {
        SCOPED_TRACE(method + ", " + s.name + ", outside " + kind.name);
        Image want;
        try {
          want = render_with(replaced, method);
        } catch (const Error&) {
          continue;  // a method may refuse a style; then it must refuse it either way
        }
        Image got;
        ASSERT_NO_THROW(got = render_with(missing, method));
        ASSERT_EQ(non_finite_pixels(got), 0);
        const double direct = psnr(got, want);
        const double with_data = std::min(psnr(want, truth), 99.0);
        const double without = std::min(psnr(got, truth), 99.0);
        EXPECT_GE(without, with_data - 1.0) << "PSNR against the reference " << without
                                            << " dB, the replaced map's " << with_data << " dB";
        worst_margin = std::min(worst_margin, without - with_data);
        worst_direct = std::min(worst_direct, direct);
        if (kind.name == "mixed")
          std::printf(
              "  %-12s %-9s vs reference: %6.2f dB (replaced map %6.2f dB); "
              "vs replaced map %6.2f dB\n",
              method.c_str(), s.name, without, with_data, direct);
      }
    }
  }
  std::printf("worst margin %.2f dB, worst PSNR against the replaced map %.2f dB\n", worst_margin,
              worst_direct);
}

// X-ray's average mode averages over the data only: a ray through the blob sees the blob's
// mean, whatever length of no data the ray also crosses; no pixel is NaN.
TEST(NoDataRender, XrayAverageIsTheMeanOfTheDataOnly) {
  StyleCase s{"xray-average", VolumeStyle::xray, XrayMode::average, false, 0.0f, {}};
  s.tf.points = {{0.0, glm::vec4(0.0f)}, {100.0, glm::vec4(1.0f, 1.0f, 1.0f, 1.0f)}};
  for (const Outside& kind : no_data_kinds()) {
    Scene missing = blob_scene(s, blob(false, kind));
    missing.image.background = glm::vec4(0.0f);
    for (const std::string& method : available_methods()) {
      SCOPED_TRACE(method + ", outside " + kind.name);
      Image got;
      try {
        got = render_with(missing, method);
      } catch (const Error&) {
        continue;
      }
      ASSERT_EQ(non_finite_pixels(got), 0);
      // The centre pixel's ray passes within a voxel of the blob's centre: the mean of the cone
      // 100 (1 - r / R) along a diameter is 50, where the TF's opacity is 0.5, and a little more
      // where the rim's lowest values, whose samples read no data, are left out (0.55 at 1.2
      // voxels). Counting no data as 0 over the whole ray (34 mm in the box) would give 0.35.
      EXPECT_NEAR(got.at(kImage / 2, kImage / 2).a, 0.55f, 0.05f);
    }
  }
}

// An MPR plane shows nothing where its volume has no data: the background shows through there,
// and the data where there is some.
TEST(NoDataRender, PlanesShowNothingWhereTheVolumeHasNoData) {
  StyleCase s{"hidden", VolumeStyle::dvr, XrayMode::integral, false, 0.0f, {}};
  s.tf.points = {{0.0, glm::vec4(0.0f)}};  // the volume itself shows nothing
  for (const Outside& kind : no_data_kinds()) {
    Scene scene = blob_scene(s, blob(false, kind));
    scene.camera.eye = {0.0, -80.0, 0.0};
    scene.image.background = {0.0f, 0.0f, 0.0f, 0.0f};
    PlaneObject plane;
    plane.name = "axial";
    plane.normal = {0, -1, 0};
    plane.up = {0, 0, 1};
    plane.size = {60, 60};
    plane.volume = 0;
    plane.window = {50.0, 100.0};
    scene.planes.push_back(plane);
    scene.order.push_back({ObjectKind::plane, 0});
    for (const std::string& method : available_methods()) {
      SCOPED_TRACE(method + ", outside " + kind.name);
      Image got;
      try {
        got = render_with(scene, method);
      } catch (const Error&) {
        continue;
      }
      ASSERT_EQ(non_finite_pixels(got), 0);
      EXPECT_GT(got.at(kImage / 2, kImage / 2).a, 0.99f) << "the blob's middle shows";
      // A corner pixel meets the plane inside the volume's box, outside the blob.
      const int corner = kImage / 2 - 14;
      EXPECT_EQ(got.at(corner, corner).a, 0.0f) << "no data shows nothing";
    }
  }
}

}  // namespace
}  // namespace imx
