// Clip planes on tubes: nothing on the removed side, a flat cap where a plane cuts a tube (at the
// plane's depth, in the tube's colour there), and the cap test against the exact distance.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include "core/colour.hpp"
#include "tube_rod.hpp"
#include "tubes/tube_cache.hpp"
#include "tubes/tube_clip.hpp"
#include "tubes/tube_fragments.hpp"
#include "tubes/tube_geometry.hpp"

namespace imx {
namespace {

std::vector<Fragment> fragments(const StreamlineObject& o, const TubeGeometry& tubes,
                                const Ray& ray) {
  const TubeLook look = make_tube_look(o, tubes);
  std::vector<Fragment> out;
  append_tube_fragments(look, ray, 1e9f, 0, {}, out);
  return out;
}

// The grey the rod has at x (value x over [-10, 10]), linear: the grey map gives display greys
// (docs/colour.md).
float grey_at(float x) {
  return srgb_decode((x + 10.0f) / 20.0f);
}

TEST(TubeClip, NothingShowsOnTheRemovedSide) {
  StreamlineObject o = test::rod(0.5, 1.0f);
  o.clip_planes.push_back({{2.0, 0.0, 0.0}, {1.0, 0.0, 0.0}});  // keeps x >= 2
  const TubeGeometry tubes(o);
  for (float x : {-9.0f, -3.0f, 0.0f, 1.8f})
    EXPECT_TRUE(fragments(o, tubes, Ray{{x, 0.1f, -20.0f}, {0, 0, 1}}).empty()) << x;
  for (float x : {2.2f, 5.0f, 9.0f}) {
    const auto out = fragments(o, tubes, Ray{{x, 0.1f, -20.0f}, {0, 0, 1}});
    ASSERT_EQ(out.size(), 1u) << x;  // opaque: the nearest crossing alone
    EXPECT_NEAR(out[0].t, 20.0f - std::sqrt(0.25f - 0.01f), 1e-4f);
  }
}

TEST(TubeClip, ACutTubeIsCappedOnThePlaneInItsColourThere) {
  for (float opacity : {1.0f, 0.4f}) {
    StreamlineObject o = test::rod(0.5, opacity);
    const float plane_x = 1.25f;
    o.clip_planes.push_back({{plane_x, 0.0, 0.0}, {1.0, 0.0, 0.0}});
    const TubeGeometry tubes(o);
    const float a = tube_fragment_alpha(opacity);
    // Looking along +x, exactly along the tube's axis, at the cut face: the first fragment is
    // the cap, on the plane.
    const glm::vec3 dir(1.0f, 0.0f, 0.0f);
    for (float y : {0.0f, 0.3f, -0.4f}) {
      const Ray ray{{-30.0f, y, 0.1f}, dir};
      const auto out = fragments(o, tubes, ray);
      ASSERT_FALSE(out.empty()) << y;
      EXPECT_NEAR(out[0].t, (plane_x + 30.0f) / dir.x, 1e-4f) << y;  // the plane's depth
      EXPECT_EQ(out[0].front_facing, 1u);
      EXPECT_NEAR(out[0].color.a, a, 1e-6f);
      EXPECT_NEAR(out[0].color.r, grey_at(plane_x) * a, 2e-3f);  // not the far end's grey
      // Translucent: then the tube's far end, leaving.
      if (opacity < 1.0f) {
        ASSERT_EQ(out.size(), 2u);
        EXPECT_EQ(out[1].front_facing, 0u);
        EXPECT_GT(out[1].t, 10.0f + 30.0f);
      } else {
        EXPECT_EQ(out.size(), 1u);
      }
    }
    // Beside the tube, the plane shows nothing.
    EXPECT_TRUE(fragments(o, tubes, Ray{{-30.0f, 0.55f, 0.0f}, {1, 0, 0}}).empty());
    // From the kept side looking back: the tube's far end, then the cap, leaving.
    if (opacity < 1.0f) {
      const glm::vec3 back_dir(-dir.x, dir.y, dir.z);
      const auto back = fragments(o, tubes, Ray{{30.0f, 0.2f, 0.0f}, back_dir});
      ASSERT_EQ(back.size(), 2u);
      EXPECT_EQ(back[1].front_facing, 0u);
      EXPECT_NEAR(back[1].t, (30.0f - plane_x) / dir.x, 1e-4f);
      EXPECT_NEAR(back[1].color.r, grey_at(plane_x) * a, 2e-3f);
    }
  }
}

TEST(TubeClip, AnObliqueRayMeetsTheCapWhereItCrossesThePlane) {
  StreamlineObject o = test::rod(1.0, 1.0f);
  const glm::dvec3 n = glm::normalize(glm::dvec3(1.0, 0.5, 0.25));
  o.clip_planes.push_back({{0.0, 0.0, 0.0}, n});
  const TubeGeometry tubes(o);
  const glm::vec3 dir = glm::normalize(glm::vec3(1.0f, -0.3f, 0.2f));
  const glm::vec3 target(0.0f, 0.1f, -0.2f);  // on the plane (n . target = 0) inside the tube
  ASSERT_NEAR(glm::dot(glm::dvec3(target), n), 0.0, 1e-6);
  const Ray ray{target - 25.0f * dir, dir};
  const auto out = fragments(o, tubes, ray);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].t, 25.0f, 1e-3f);
  EXPECT_NEAR(out[0].color.r, grey_at(0.0f), 0.05f);
}

TEST(TubeClip, TwoPlanesKeepTheSlabBetweenThemWithACapAtEach) {
  StreamlineObject o = test::rod(0.5, 0.5f);
  o.clip_planes.push_back({{-2.0, 0.0, 0.0}, {1.0, 0.0, 0.0}});  // x >= -2
  o.clip_planes.push_back({{3.0, 0.0, 0.0}, {-1.0, 0.0, 0.0}});  // x <= 3
  const TubeGeometry tubes(o);
  const glm::vec3 dir = glm::normalize(glm::vec3(1.0f, 0.002f, 0.0f));
  const auto out = fragments(o, tubes, Ray{{-30.0f, 0.1f, 0.1f}, dir});
  ASSERT_EQ(out.size(), 2u);  // the tube's own ends are removed: a cap at each plane
  EXPECT_NEAR(out[0].t, 28.0f / dir.x, 1e-4f);
  EXPECT_NEAR(out[1].t, 33.0f / dir.x, 1e-4f);
  EXPECT_EQ(out[0].front_facing, 1u);
  EXPECT_EQ(out[1].front_facing, 0u);
}

TEST(TubeClip, TheCapTestIsTheDistanceToTheNearestSegment) {
  // Random short streamlines around the origin, a tilted plane through it.
  Streamlines s;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> coord(-8.0f, 8.0f), step(-1.5f, 1.5f);
  for (int line = 0; line < 60; ++line) {
    glm::vec3 p(coord(rng), coord(rng), coord(rng));
    for (int i = 0; i < 12; ++i, p += glm::vec3(step(rng), step(rng), step(rng)))
      s.points.push_back(p);
    s.offsets.push_back(static_cast<uint32_t>(s.points.size()));
  }
  StreamlineObject o;
  o.radius = 0.7;
  o.streamlines = std::make_shared<const Streamlines>(s);
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.8f, 0.5f));
  o.clip_planes.push_back({{0.5, 0.2, -0.1}, glm::dvec3(n)});
  const TubeGeometry tubes(o);
  const glm::vec3 q(0.5f, 0.2f, -0.1f);
  const glm::vec3 e1 = glm::normalize(glm::cross(n, glm::vec3(0, 0, 1))), e2 = glm::cross(n, e1);
  std::uniform_real_distribution<float> in_plane(-12.0f, 12.0f);
  size_t inside = 0;
  for (int k = 0; k < 20000; ++k) {
    const glm::vec3 p = q + in_plane(rng) * e1 + in_plane(rng) * e2;
    float nearest = 1e30f;
    for (size_t l = 0; l + 1 < s.offsets.size(); ++l)
      for (uint32_t i = s.offsets[l]; i + 1 < s.offsets[l + 1]; ++i) {
        const glm::vec3 a = s.points[i], ab = s.points[i + 1] - a;
        const float u = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0f, 1.0f);
        nearest = std::min(nearest, glm::length(p - a - u * ab));
      }
    if (std::abs(nearest - 0.7f) < 1e-4f) continue;  // on the surface: either answer
    TubeHit at;
    const bool got = tubes.contains(p, &at);
    EXPECT_EQ(got, nearest < 0.7f) << k << " distance " << nearest;
    inside += got;
  }
  EXPECT_GT(inside, 200u);
}

// A viewer's frames keep the tubes when the planes move, and the cut follows the planes.
TEST(TubeClip, MovingAPlaneMovesTheCutNotTheTubes) {
  StreamlineObject o = test::rod(0.5, 1.0f);
  o.cache = make_tube_cache();
  o.clip_planes.push_back({{2.0, 0.0, 0.0}, {1.0, 0.0, 0.0}});
  const auto tubes = tube_geometry(o);
  ASSERT_NE(make_tube_look(o, *tubes).clip, nullptr);
  EXPECT_FALSE(fragments(o, *tubes, Ray{{2.5f, 0.1f, -20.0f}, {0, 0, 1}}).empty());
  o.clip_planes[0].point.x = 3.0;
  EXPECT_EQ(tube_geometry(o), tubes);
  EXPECT_TRUE(fragments(o, *tubes, Ray{{2.5f, 0.1f, -20.0f}, {0, 0, 1}}).empty());
  o.clip_planes.clear();
  EXPECT_EQ(make_tube_look(o, *tubes).clip, nullptr);
}

}  // namespace
}  // namespace imx
