// Silhouette coverage: a tube covers the part of a pixel its radius reaches, so thin tubes stay
// continuous at one sample per pixel and their edges ramp instead of stepping.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tubes/tube_coverage.hpp"
#include "tubes/tube_fragments.hpp"
#include "tubes/tube_geometry.hpp"

namespace imx {
namespace {

// One streamline from (x0, y0) to (x1, y1) at z = 0, points every `step` mm along it.
StreamlineObject line_object(glm::vec2 a, glm::vec2 b, float step, double radius) {
  Streamlines s;
  s.offsets = {0};
  const float length = glm::length(b - a);
  const int n = static_cast<int>(std::ceil(length / step));
  for (int i = 0; i <= n; ++i) {
    const glm::vec2 p = a + (b - a) * (static_cast<float>(i) / n);
    s.points.push_back({p.x, p.y, 0.0f});
  }
  s.offsets.push_back(static_cast<uint32_t>(s.points.size()));
  StreamlineObject o;
  o.name = "thin";
  o.radius = radius;
  o.shading = Shading{false};
  o.colouring = StreamlineColouring::fixed;
  o.streamlines = std::make_shared<const Streamlines>(std::move(s));
  return o;
}

// What a pixel's fragments hide: 1 - the product of what each lets through.
float pixel_alpha(const TubeLook& look, const Ray& ray) {
  std::vector<Fragment> out;
  append_tube_fragments(look, ray, 1e9f, 0, {}, out);
  float through = 1.0f;
  for (const Fragment& f : out) through *= 1.0f - f.color.a;
  return 1.0f - through;
}

TEST(TubeSilhouetteAa, CoverageRampsAcrossOnePixelAtTheRadius) {
  EXPECT_FLOAT_EQ(tube_coverage(1.0f, 1.0f, 0.5f), 0.5f);
  EXPECT_FLOAT_EQ(tube_coverage(1.0f, 0.75f, 0.5f), 1.0f);
  EXPECT_FLOAT_EQ(tube_coverage(1.0f, 1.25f, 0.5f), 0.0f);
  EXPECT_NEAR(tube_coverage(1.0f, 1.125f, 0.5f), 0.25f, 1e-6f);
  // Half the footprint, rounded up to a step of 2^(1/8).
  EXPECT_FLOAT_EQ(silhouette_pad(0.5f), 0.25f);
  EXPECT_FLOAT_EQ(silhouette_pad(0.6f), std::exp2(-13.0f / 8.0f));
  for (float fp : {0.01f, 0.37f, 3.3f}) {
    EXPECT_GE(silhouette_pad(fp), 0.5f * fp);
    EXPECT_LE(silhouette_pad(fp), 0.5f * fp * 1.0906f);
  }
}

TEST(TubeSilhouetteAa, ARayThroughTheAxisCrossesTheTrueRadiusAndANearMissIsPartial) {
  const float fp = 0.5f, radius = 1.0f;
  StreamlineObject o = line_object({-20.0f, 0.0f}, {20.0f, 0.0f}, 2.0f, radius);
  TubeGeometry tubes(o, silhouette_pad(fp));
  TubeLook look = make_tube_look(o, tubes);
  enable_silhouette_aa(look, fp, 0.0f);
  // Opaque: the entry alone, what lies behind it hidden (as without coverage).
  std::vector<Fragment> out;
  append_tube_fragments(look, Ray{{0.3f, 0.0f, -10.0f}, {0, 0, 1}}, 1e9f, 0, {}, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].t, 10.0f - radius, 1e-4f);
  // Translucent: the entry and the exit, nearest first.
  StreamlineObject half = o;
  half.opacity = 0.5f;
  TubeLook half_look = make_tube_look(half, tubes);
  enable_silhouette_aa(half_look, fp, 0.0f);
  out.clear();
  append_tube_fragments(half_look, Ray{{0.3f, 0.0f, -10.0f}, {0, 0, 1}}, 1e9f, 0, {}, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0].t, 10.0f - radius, 1e-4f);
  EXPECT_NEAR(out[1].t, 10.0f + radius, 1e-4f);
  EXPECT_NEAR(pixel_alpha(look, Ray{{0.3f, 0.0f, -10.0f}, {0, 0, 1}}), 1.0f, 1e-5f);
  // A quarter of a pixel past the edge's middle: a quarter covered, though the ray misses.
  const float y = radius + 0.25f * fp;
  EXPECT_NEAR(pixel_alpha(look, Ray{{0.3f, y, -10.0f}, {0, 0, 1}}), tube_coverage(radius, y, fp),
              1e-4f);
  EXPECT_NEAR(tube_coverage(radius, y, fp), 0.25f, 1e-6f);
  EXPECT_EQ(pixel_alpha(look, Ray{{0.3f, radius + fp, -10.0f}, {0, 0, 1}}), 0.0f);
  // Without coverage the same near miss is empty.
  TubeGeometry plain(o);
  EXPECT_EQ(pixel_alpha(make_tube_look(o, plain), Ray{{0.3f, y, -10.0f}, {0, 0, 1}}), 0.0f);
  // Nor through the padded geometry when coverage is off (a cache keeps one for both).
  TubeLook hard = make_tube_look(o, tubes);
  hard_tubes_through_pad(hard);
  EXPECT_EQ(pixel_alpha(hard, Ray{{0.3f, y, -10.0f}, {0, 0, 1}}), 0.0f);
  out.clear();
  append_tube_fragments(hard, Ray{{0.3f, radius - 0.05f, -10.0f}, {0, 0, 1}}, 1e9f, 0, {}, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].t, 10.0f - std::sqrt(radius * radius - 0.95f * 0.95f), 1e-3f);
  EXPECT_FLOAT_EQ(out[0].color.a, 1.0f);
}

// Per column of a 512 x 512 orthographic image (0.5 mm pixels) across a 0.2 mm radius tube
// drawn at a slant: the summed coverage, and how many columns on the tube have none.
struct Columns {
  int gaps = 0;
  float worst_error = 0.0f;  // of the summed coverage against the tube's width in pixels
};

Columns columns(bool aa) {
  const float fp = 0.5f, radius = 0.2f;
  const glm::vec2 a{10.0f, 40.0f}, b{246.0f, 110.0f};
  StreamlineObject o = line_object(a, b, 5.0f, radius);
  TubeGeometry tubes(o, aa ? silhouette_pad(fp) : 0.0f);
  TubeLook look = make_tube_look(o, tubes);
  if (aa) enable_silhouette_aa(look, fp, 0.0f);
  const float slope = (b.y - a.y) / (b.x - a.x);
  // Across a column, the tube's 2r wide band spans 2r / cos(angle) mm of y.
  const float expected = 2.0f * radius / fp * std::sqrt(1.0f + slope * slope);
  Columns c;
  for (int x = 30; x < 482; ++x) {
    const float cx = (x + 0.5f) * fp, cy = a.y + slope * (cx - a.x);
    const int y0 = static_cast<int>(cy / fp);
    float sum = 0.0f;
    for (int y = y0 - 4; y <= y0 + 4; ++y)
      sum += pixel_alpha(look, Ray{{cx, (y + 0.5f) * fp, -10.0f}, {0, 0, 1}});
    if (sum < 0.05f) ++c.gaps;
    c.worst_error = std::max(c.worst_error, std::abs(sum - expected) / expected);
  }
  return c;
}

TEST(TubeSilhouetteAa, ASubPixelTubeIsContinuousWithItsWidthAsCoverage) {
  const Columns plain = columns(false), covered = columns(true);
  RecordProperty("gaps_without", plain.gaps);
  RecordProperty("gaps_with", covered.gaps);
  RecordProperty("width_error_with", std::to_string(covered.worst_error));
  EXPECT_GT(plain.gaps, 0);  // the one-sample tube is dotted: what this fixes
  EXPECT_EQ(covered.gaps, 0);
  EXPECT_LT(covered.worst_error, 0.1f);
}

}  // namespace
}  // namespace imx
