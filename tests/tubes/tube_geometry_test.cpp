// TubeGeometry: exact entry and exit depths of round tubes, and the nearest-hits query against
// every hit sorted by hand.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tubes/tube_fragments.hpp"
#include "tubes/tube_geometry.hpp"

namespace imx {
namespace {

// A straight streamline along x from x0 to x1 at (y, z), with points every `step` mm.
void add_line(Streamlines& s, float x0, float x1, float step, float y, float z) {
  for (float x = x0; x <= x1 + 1e-4f; x += step) s.points.push_back({x, y, z});
  s.offsets.push_back(static_cast<uint32_t>(s.points.size()));
}

StreamlineObject object_of(Streamlines s, double radius) {
  StreamlineObject o;
  o.name = "test";
  o.radius = radius;
  o.streamlines = std::make_shared<const Streamlines>(std::move(s));
  return o;
}

TEST(TubeGeometry, ARayThroughATubeEntersAndLeavesAtTheCylinder) {
  Streamlines s;
  add_line(s, -10.0f, 10.0f, 0.5f, 0.0f, 0.0f);
  const TubeGeometry tubes(object_of(std::move(s), 0.5));
  EXPECT_EQ(tubes.segment_count(), 40u);
  for (float y : {0.0f, 0.3f, -0.45f}) {
    const Ray ray{{1.23f, y, -20.0f}, {0.0f, 0.0f, 1.0f}};
    std::vector<TubeHit> hits(8);
    ASSERT_EQ(tubes.nearest_hits(ray, 0.0f, 1e9f, hits), 2u) << "y " << y;
    const float half = std::sqrt(0.25f - y * y);
    EXPECT_NEAR(hits[0].t, 20.0f - half, 1e-4f);
    EXPECT_NEAR(hits[1].t, 20.0f + half, 1e-4f);
    EXPECT_LT(hits[0].normal.z, 0.0f);  // the entry faces the ray
    EXPECT_GT(hits[1].normal.z, 0.0f);
  }
  // Beside the tube: nothing.
  std::vector<TubeHit> hits(8);
  EXPECT_EQ(tubes.nearest_hits(Ray{{1.0f, 0.51f, -20.0f}, {0, 0, 1}}, 0.0f, 1e9f, hits), 0u);
  // Past the end cap's sphere: nothing; on it: a hit on the round cap.
  EXPECT_EQ(tubes.nearest_hits(Ray{{10.6f, 0.0f, -20.0f}, {0, 0, 1}}, 0.0f, 1e9f, hits), 0u);
  ASSERT_EQ(tubes.nearest_hits(Ray{{10.3f, 0.0f, -20.0f}, {0, 0, 1}}, 0.0f, 1e9f, hits), 2u);
  EXPECT_NEAR(hits[0].t, 20.0f - std::sqrt(0.25f - 0.09f), 1e-3f);
}

TEST(TubeGeometry, ContainsIsWithinTheRadiusOfTheNearestSegment) {
  Streamlines s;
  add_line(s, 0.0f, 10.0f, 1.0f, 0.0f, 0.0f);
  add_line(s, 0.0f, 10.0f, 1.0f, 5.0f, 0.0f);
  const TubeGeometry tubes(object_of(std::move(s), 1.0));
  TubeHit where;
  ASSERT_TRUE(tubes.contains({5.5f, 0.9f, 0.0f}, &where));
  EXPECT_EQ(where.segment, 5u);  // the first streamline's sixth segment, x 5..6
  EXPECT_NEAR(where.u, 0.5f, 1e-5f);
  EXPECT_NEAR(where.normal.y, 0.9f, 1e-5f);  // from the axis to the point
  EXPECT_FALSE(tubes.contains({5.5f, 1.1f, 0.0f}));
  ASSERT_TRUE(tubes.contains({3.2f, 5.0f, -0.95f}, &where));
  EXPECT_EQ(where.segment, 13u);                      // the second streamline's fourth
  EXPECT_TRUE(tubes.contains({10.7f, 0.0f, 0.0f}));   // in the round end cap
  EXPECT_FALSE(tubes.contains({10.0f, 0.8f, 0.8f}));  // beyond it, beside the axis's end
  EXPECT_FALSE(tubes.contains({5.0f, 2.5f, 0.0f}));   // between the tubes
}

TEST(TubeGeometry, NearestHitsAreTheNearestOfAllInOrder) {
  // A stack of parallel tubes along z, so a ray along z crosses them all.
  Streamlines s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> jitter(-0.2f, 0.2f);
  for (int i = 0; i < 40; ++i) add_line(s, -5.0f, 5.0f, 1.0f, jitter(rng), 2.0f * i);
  const TubeGeometry tubes(object_of(std::move(s), 0.5));
  const Ray ray{{0.1f, 0.0f, -10.0f}, {0.0f, 0.0f, 1.0f}};
  std::vector<TubeHit> all(200);
  const size_t n = tubes.nearest_hits(ray, 0.0f, 1e9f, all);
  ASSERT_EQ(n, 80u);  // in and out of each
  for (size_t i = 1; i < n; ++i) EXPECT_LE(all[i - 1].t, all[i].t);
  for (size_t k : {1u, 5u, 16u, 33u}) {
    std::vector<TubeHit> nearest(k);
    ASSERT_EQ(tubes.nearest_hits(ray, 0.0f, 1e9f, nearest), k);
    for (size_t i = 0; i < k; ++i) EXPECT_FLOAT_EQ(nearest[i].t, all[i].t) << k << " " << i;
    // Continuing after the last gives the next ones.
    std::vector<TubeHit> next(3);
    ASSERT_EQ(tubes.nearest_hits(ray, nearest[k - 1].t, 1e9f, next), 3u);
    EXPECT_FLOAT_EQ(next[0].t, all[k].t);
  }
}

TEST(TubeGeometry, StrideAndMinimumLengthSelectStreamlines) {
  Streamlines s;
  for (int i = 0; i < 10; ++i) add_line(s, 0.0f, i < 5 ? 2.0f : 20.0f, 1.0f, 3.0f * i, 0.0f);
  StreamlineObject o = object_of(std::move(s), 0.5);
  o.stride = 2;
  EXPECT_EQ(TubeGeometry(o).streamline_count(), 5u);
  o.stride = 1;
  o.min_length = 10.0;
  EXPECT_EQ(TubeGeometry(o).streamline_count(), 5u);
  StreamlineRegion sphere;
  sphere.radius = 1.0;  // at the origin
  o.regions.push_back(sphere);
  EXPECT_EQ(TubeGeometry(o).streamline_count(), 0u);  // only streamline 0 passes, and it is short
  o.min_length = 0.0;
  EXPECT_EQ(TubeGeometry(o).streamline_count(), 1u);
  o.regions[0].avoid = true;
  EXPECT_EQ(TubeGeometry(o).streamline_count(), 9u);
}

TEST(TubeFragments, ACrossingLetsThroughWhatItsOpacitySays) {
  for (float opacity : {0.0f, 0.3f, 0.9f, 1.0f}) {
    const float a = tube_fragment_alpha(opacity);
    EXPECT_NEAR((1.0f - a) * (1.0f - a), 1.0f - opacity, 1e-6f);
  }
}

TEST(TubeFragments, DirectionColourIsTheSegmentsAbsoluteDirection) {
  Streamlines s;
  s.points = {{0, 0, 0}, {0, 6, 8}};
  s.offsets = {0, 2};
  StreamlineObject o = object_of(std::move(s), 1.0);
  o.shading.enabled = false;
  o.opacity = 0.3f;
  const TubeGeometry tubes(o);
  const TubeLook look = make_tube_look(o, tubes);
  std::vector<Fragment> out;
  append_tube_fragments(look, Ray{{-20.0f, 3.0f, 4.0f}, {1, 0, 0}}, 1e9f, 7, {}, out);
  ASSERT_EQ(out.size(), 2u);
  const float a = tube_fragment_alpha(0.3f);
  for (const Fragment& f : out) {
    EXPECT_EQ(f.object, 7u);
    EXPECT_NEAR(f.color.a, a, 1e-6f);
    EXPECT_NEAR(f.color.r, 0.0f, 1e-6f);
    EXPECT_NEAR(f.color.g, 0.6f * a, 1e-5f);
    EXPECT_NEAR(f.color.b, 0.8f * a, 1e-5f);
  }
  EXPECT_EQ(out[0].front_facing, 1u);
  EXPECT_EQ(out[1].front_facing, 0u);
  EXPECT_NEAR(out[0].t, 19.0f, 1e-4f);
}

TEST(TubeFragments, ValueColouringNamesTheMissingValues) {
  Streamlines s;
  s.points = {{0, 0, 0}, {0, 6, 8}};
  s.offsets = {0, 2};
  s.point_values.push_back({"fa", {0.0f, 1.0f}});
  StreamlineObject o = object_of(std::move(s), 1.0);
  o.colouring = StreamlineColouring::point_value;
  o.value = "md";
  const TubeGeometry tubes(o);
  try {
    make_tube_look(o, tubes);
    FAIL();
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("'md' (it has 'fa')"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace imx
