#include "volume/projection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "each_simd_target.hpp"
#include "random_volumes.hpp"
#include "volume/packet_projection.hpp"

namespace imx {
namespace {

using test::prepared;
using test::random_ray;

constexpr int kBisections = 10;

glm::vec4 walk(const PreparedVolume& v, const Ray& ray, RayInterval span, float step) {
  VolumeHit hit;
  const KeptSpan whole(span);
  const bool found = v.object->style == VolumeStyle::iso
                         ? find_iso_crossing(v, ray, whole, step, kBisections, {}, hit)
                         : project_volume(v, ray, whole, step, hit);
  return found ? hit.color : glm::vec4(0.0f);
}

float max_difference(glm::vec4 a, glm::vec4 b) {
  float worst = 0.0f;
  for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(a[c] - b[c]));
  return worst;
}

// Skipping by brick ranges (scalar walk, and lanes on every SIMD target) against the plain walk
// that samples every point, for every projection style and iso, on blob volumes whose TFs have
// empty bands. `no_data`: float voxels of the background and a few others made NaN or inf.
template <class T>
void check_style(VolumeStyle style, float scale, float offset, uint32_t seed,
                 bool no_data = false) {
  std::mt19937 rng(seed);
  int shown = 0, total = 0;
  for (int trial = 0; trial < 6; ++trial) {
    VolumeObject obj;
    obj.name = "blobs";
    obj.style = style;
    obj.iso_value = offset + scale * (60.0f + 20.0f * static_cast<float>(trial));
    const glm::ivec3 dims(37, 29, 33);
    auto data = std::make_shared<VolumeData>(test::blob_volume<T>(dims, rng, scale, offset));
    if (no_data) test::punch_no_data(*data, rng, offset + 20.0f * scale);
    obj.data = data;
    obj.index_to_world = glm::dmat4(glm::dmat3(0.9, 0.1, 0.0, -0.1, 1.1, 0.0, 0.0, 0.2, 1.3));
    obj.transfer_function = test::random_tf(rng, offset, offset + 255.0f * scale);
    if (trial % 2 == 0)  // nothing below a threshold: MIP may skip TF-empty bricks as well
      obj.transfer_function.points.front().rgba.a = 0.0f;
    if (style == VolumeStyle::minip) {  // the minimum shows, nothing does above a threshold
      obj.transfer_function.points.front().rgba.a = 0.6f;
      if (trial % 2 == 0) obj.transfer_function.points.back().rgba.a = 0.0f;
    }
    if (style == VolumeStyle::iso)
      obj.transfer_function.points = {{obj.iso_value, glm::vec4(1.0f)}};
    const float step = trial == 3 ? 0.37f : 0.8f;
    const SkipMode skip = trial % 3 == 0 ? SkipMode::bricks : SkipMode::distance;
    PreparedVolume plain =
        prepared(obj, step, {SkipMode::none, Classification::post, GradientSource::on_the_fly, 4});
    PreparedVolume skipping =
        prepared(obj, step, {skip, Classification::post, GradientSource::on_the_fly, 4});
    ASSERT_TRUE(skipping.accel.ranges);
    std::vector<PacketRay> rays;
    for (int k = 0; k < 301; ++k) {
      const Ray ray = random_ray(rng, glm::vec3(dims) * 0.5f, 1.2f * dims.x);
      const RayInterval span = skipping.intersect(ray);
      rays.push_back({ray, span.t0, span.t1});
    }
    std::vector<glm::vec4> expected(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
      const RayInterval span{rays[i].t0, rays[i].t1};
      expected[i] = walk(plain, rays[i].ray, span, step);
      EXPECT_LE(max_difference(walk(skipping, rays[i].ray, span, step), expected[i]), 1e-5f)
          << "ray " << i << " trial " << trial;
      shown += expected[i].a > 0.0f;
      ++total;
    }
    test::for_each_simd_target([&](const std::string&) {
      std::vector<glm::vec4> lanes(rays.size());
      project_packets(skipping, rays, step, kBisections, {}, lanes);
      // The lanes place points in floats: a maximum may land a rounding apart.
      size_t apart = 0;
      for (size_t i = 0; i < rays.size(); ++i)
        apart += max_difference(lanes[i], expected[i]) > 2e-3f;
      EXPECT_LE(apart, rays.size() / 50) << "trial " << trial;
    });
  }
  EXPECT_GT(shown, total / 10);  // the rays see something
}

TEST(Projection, SkippingKeepsMipU8) {
  check_style<uint8_t>(VolumeStyle::mip, 1.0f, 0.0f, 1);
}
TEST(Projection, SkippingKeepsMipI16) {
  check_style<int16_t>(VolumeStyle::mip, 8.0f, -1000.0f, 2);
}
TEST(Projection, SkippingKeepsMinipU16) {
  check_style<uint16_t>(VolumeStyle::minip, 200.0f, 0.0f, 3);
}
TEST(Projection, SkippingKeepsMinipFloat) {
  check_style<float>(VolumeStyle::minip, 0.01f, -0.5f, 4);
}
TEST(Projection, SkippingKeepsXrayU8) {
  check_style<uint8_t>(VolumeStyle::xray, 1.0f, 0.0f, 5);
}
TEST(Projection, SkippingKeepsXrayI16) {
  check_style<int16_t>(VolumeStyle::xray, 8.0f, -1000.0f, 6);
}
TEST(Projection, SkippingKeepsIsoU8) {
  check_style<uint8_t>(VolumeStyle::iso, 1.0f, 0.0f, 7);
}
TEST(Projection, SkippingKeepsIsoFloat) {
  check_style<float>(VolumeStyle::iso, 0.01f, -0.5f, 8);
}
// The same with no data (NaN and inf voxels): skipped alike by the walks and the lanes.
TEST(Projection, SkippingKeepsEveryStyleWithNoData) {
  for (VolumeStyle style :
       {VolumeStyle::mip, VolumeStyle::minip, VolumeStyle::xray, VolumeStyle::iso}) {
    SCOPED_TRACE(static_cast<int>(style));
    check_style<float>(style, 0.01f, -0.5f, 20 + static_cast<int>(style), true);
  }
}

// A block of constant value seen along x through `length` voxels of 1 mm.
struct ConstantBlock {
  VolumeObject obj;
  explicit ConstantBlock(int length, XrayMode mode) {
    auto data = std::make_shared<VolumeData>();
    data->dims = {length, 4, 4};
    data->voxels = std::vector<uint8_t>(static_cast<size_t>(length) * 4 * 4, 100);
    obj.name = "slab";
    obj.style = VolumeStyle::xray;
    obj.xray_mode = mode;
    obj.data = data;
    obj.transfer_function.points = {{0.0, glm::vec4(0.5f, 0.5f, 0.5f, 0.1f)},
                                    {255.0, glm::vec4(0.5f, 0.5f, 0.5f, 0.1f)}};
  }
  float opacity() const {
    PreparedVolume v(obj);
    const Ray ray{glm::vec3(-5.0f, 1.5f, 1.5f), glm::vec3(1.0f, 0.0f, 0.0f)};
    const RayInterval span = v.intersect(ray);
    return walk(v, ray, span, 0.25f).a;
  }
};

TEST(Projection, XrayIntegralShowsThickness) {
  // 0.1 of opacity per mm is an attenuation of -ln(0.9) per mm: I = 1 - 0.9^length.
  for (int length : {6, 11, 21})
    EXPECT_NEAR(ConstantBlock(length, XrayMode::integral).opacity(),
                1.0 - std::pow(0.9, length - 1), 1e-4)
        << length;
  // The average shows the TF at the mean value, whatever the thickness.
  EXPECT_NEAR(ConstantBlock(6, XrayMode::average).opacity(), 0.1f, 1e-6f);
  EXPECT_NEAR(ConstantBlock(21, XrayMode::average).opacity(), 0.1f, 1e-6f);
}

TEST(Projection, LimitsFollowTheTable) {
  TransferFunction tf;
  tf.points = {{100.0, glm::vec4(1.0f, 1.0f, 1.0f, 0.0f)}, {200.0, glm::vec4(1.0f)}};
  TfLut lut(tf);
  ProjectionLimits l = projection_limits(lut);
  EXPECT_GT(l.invisible_up_to, 99.9f);
  EXPECT_LE(l.invisible_up_to, 100.0f);
  EXPECT_EQ(lut.lookup(l.invisible_up_to).a, 0.0f);
  EXPECT_GT(lut.lookup(l.invisible_up_to + 0.1f).a, 0.0f);
  EXPECT_GE(l.constant_from, 200.0f);
  EXPECT_LT(l.constant_from, 200.1f);
  EXPECT_EQ(l.invisible_from, INFINITY);
  EXPECT_TRUE(l.invisible_only_below);
  EXPECT_FALSE(l.invisible_only_above);
  // A band of zero opacity above visible values: an empty brick may hold a maximum that hides.
  tf.points = {{0.0, glm::vec4(1.0f)},
               {100.0, glm::vec4(1.0f, 1.0f, 1.0f, 0.0f)},
               {200.0, glm::vec4(1.0f, 1.0f, 1.0f, 0.0f)},
               {300.0, glm::vec4(1.0f)}};
  l = projection_limits(TfLut(tf));
  EXPECT_FALSE(l.invisible_only_below);
  EXPECT_FALSE(l.invisible_only_above);
  EXPECT_EQ(l.invisible_up_to, -INFINITY);
}

}  // namespace
}  // namespace imx
