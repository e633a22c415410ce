// TubeBvh against an oracle: along a ray, a tube (the union of its segments' capsules) is the
// union of the capsules' intervals, so its crossings are the ends of the merged intervals.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include "tubes/tube_bvh.hpp"

namespace imx {
namespace {

// The interval of the ray o + t d (unit d) inside the capsule of radius r around ab, in double.
bool capsule_interval(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& a,
                      const glm::dvec3& b, double r, double& t0, double& t1) {
  // Inside the capsule where the distance to the segment is at most r: bisect the distance
  // along the ray around its minimum, found by ternary search (the distance is convex in t).
  const glm::dvec3 centre_point = 0.5 * (a + b), to_centre = centre_point - o;
  const double off_line = glm::length(to_centre - glm::dot(to_centre, d) * d);
  if (off_line > 0.5 * glm::length(b - a) + r) return false;  // far from the line: no search
  auto distance = [&](double t) {
    const glm::dvec3 x = o + t * d, ba = b - a;
    const double len2 = glm::dot(ba, ba);
    const double u = len2 > 0 ? std::clamp(glm::dot(x - a, ba) / len2, 0.0, 1.0) : 0.0;
    return glm::length(x - (a + u * ba));
  };
  const double centre = glm::dot((a + b) * 0.5 - o, d);
  double lo = centre - 1e3, hi = centre + 1e3;
  for (int i = 0; i < 200; ++i) {
    const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (distance(m1) < distance(m2)) {
      hi = m2;
    } else {
      lo = m1;
    }
  }
  const double best = 0.5 * (lo + hi);
  if (distance(best) > r) return false;
  auto edge = [&](double inside, double outside) {
    for (int i = 0; i < 100; ++i) {
      const double m = 0.5 * (inside + outside);
      (distance(m) <= r ? inside : outside) = m;
    }
    return inside;
  };
  t0 = edge(best, best - 1e3);
  t1 = edge(best, best + 1e3);
  return true;
}

TEST(TubeBvh, CrossingsAreTheEndsOfEachTubesMergedCapsuleIntervals) {
  // Gently bending streamlines on a grid, apart from each other, so that a tube overlaps only
  // its own neighbouring segments (as the BVH's joints assume).
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> U(-1.0f, 1.0f);
  std::vector<glm::vec3> points;
  std::vector<uint32_t> segment_points;
  std::vector<uint32_t> streamline_of_segment;
  const float radius = 0.5f;
  uint32_t streamline = 0;
  for (int gx = 0; gx < 6; ++gx)
    for (int gy = 0; gy < 6; ++gy, ++streamline) {
      glm::vec3 p(gx * 6.0f, gy * 6.0f, -20.0f);
      glm::vec3 dir(0.0f, 0.0f, 1.0f);
      const int n = 20 + static_cast<int>(rng() % 30);
      for (int k = 0; k < n; ++k) {
        if (k > 0) {
          segment_points.push_back(static_cast<uint32_t>(points.size() - 1));
          streamline_of_segment.push_back(streamline);
        }
        points.push_back(p);
        // At most ~0.1 rad per step: no streamline comes back to itself within 50 steps.
        dir = glm::normalize(dir + 0.1f * glm::vec3(U(rng), U(rng), 0.3f * U(rng)));
        p += (0.6f + 0.8f * (U(rng) + 1.0f)) * dir;  // steps of 0.6-2.2 mm
      }
    }
  const TubeBvh bvh({points, segment_points, radius, {}});
  int rays = 0, crossings = 0;
  Ray busiest;
  size_t most = 0;
  std::vector<TubeHit> hits(64);
  for (int i = 0; i < 400; ++i) {
    // Rays aimed near a random point of the tubes, from every direction: grazing included.
    const glm::vec3 target =
        points[rng() % points.size()] + 0.7f * glm::vec3(U(rng), U(rng), U(rng));
    const glm::vec3 d = glm::normalize(glm::vec3(U(rng), U(rng), U(rng)));
    const Ray ray{target - 100.0f * d, d};
    // The oracle: per streamline, its capsules' intervals merged; every merged end a crossing.
    std::vector<std::pair<double, bool>> expected;  // depth, entry
    for (uint32_t s = 0; s < streamline; ++s) {
      std::vector<std::pair<double, double>> spans;
      for (size_t k = 0; k < segment_points.size(); ++k) {
        if (streamline_of_segment[k] != s) continue;
        double t0, t1;
        if (capsule_interval(glm::dvec3(ray.origin), glm::dvec3(ray.dir),
                             glm::dvec3(points[segment_points[k]]),
                             glm::dvec3(points[segment_points[k] + 1]), radius, t0, t1))
          spans.push_back({t0, t1});
      }
      std::sort(spans.begin(), spans.end());
      for (size_t k = 0; k < spans.size();) {
        double end = spans[k].second;
        size_t j = k + 1;
        for (; j < spans.size() && spans[j].first <= end; ++j) end = std::max(end, spans[j].second);
        if (end - spans[k].first > 1e-3)
          expected.push_back({spans[k].first, true}), expected.push_back({end, false});
        k = j;
      }
    }
    std::sort(expected.begin(), expected.end());
    const size_t found = bvh.nearest_hits(ray, 0.0f, 1e9f, hits);
    ASSERT_LT(found, hits.size());
    ASSERT_EQ(found, expected.size()) << "ray " << i;
    for (size_t k = 0; k < found; ++k) {
      EXPECT_NEAR(hits[k].t, expected[k].first, 2e-3) << "ray " << i << " crossing " << k;
      EXPECT_NEAR(glm::length(hits[k].normal), radius, 1e-3f);  // from the axis: the radius
      // An entry faces the ray, an exit faces away.
      EXPECT_EQ(glm::dot(hits[k].normal, ray.dir) < 0.0f, expected[k].second) << "ray " << i;
    }
    if (found > most) most = found, busiest = ray;
    rays += found > 0;
    crossings += static_cast<int>(found);
  }
  EXPECT_GT(rays, 300);  // most rays were aimed at a tube
  EXPECT_GT(crossings, 2 * rays);
  // The K nearest are the nearest K of all, and a range cuts them.
  const Ray ray = busiest;
  std::vector<TubeHit> all(64), three(3), later(64);
  const size_t n = bvh.nearest_hits(ray, 0.0f, 1e9f, all);
  ASSERT_GE(n, 4u);
  ASSERT_EQ(bvh.nearest_hits(ray, 0.0f, 1e9f, three), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(three[k].t, all[k].t);
  EXPECT_EQ(bvh.nearest_hits(ray, all[1].t, 1e9f, later), n - 2);
  EXPECT_EQ(later[0].t, all[2].t);
  // A visitor is handed the same crossings, each once, with its run's points at hand; one that
  // lowers its reach to each crossing it is given still sees the nearest.
  struct Recorder final : TubeHitVisitor {
    const std::vector<glm::vec3>& points;
    const std::vector<uint32_t>& segment_points;
    bool nearest_only = false;
    std::vector<float> seen;
    int wrong_points = 0;
    Recorder(const std::vector<glm::vec3>& p, const std::vector<uint32_t>& s)
        : points(p), segment_points(s) {}
    void add(const TubeHit& hit, const TubeRunPoints& run) override {
      seen.push_back(hit.t);
      const uint32_t j = hit.segment - run.first_segment, q = segment_points[hit.segment];
      wrong_points +=
          !(j < run.segments && run.points[j] == points[q] && run.points[j + 1] == points[q + 1]);
      const uint32_t first = segment_points[run.first_segment];
      wrong_points += (run.joins & 1) && run.points[-1] != points[first - 1];
      wrong_points +=
          (run.joins & 2) && run.points[run.segments + 1] != points[first + run.segments + 1];
      if (nearest_only) reach = std::min(reach, hit.t);
    }
  } every(points, segment_points), nearest(points, segment_points);
  bvh.visit_hits(ray, every);
  std::sort(every.seen.begin(), every.seen.end());
  ASSERT_EQ(every.seen.size(), n);
  for (size_t k = 0; k < n; ++k) EXPECT_EQ(every.seen[k], all[k].t);
  EXPECT_EQ(every.wrong_points, 0);
  nearest.nearest_only = true;
  bvh.visit_hits(ray, nearest);
  EXPECT_EQ(*std::min_element(nearest.seen.begin(), nearest.seen.end()), all[0].t);
  EXPECT_LT(nearest.seen.size(), n);  // what lies behind a reach is not looked for
}

TEST(TubeBvh, ContainsFindsTheNearestSegmentWithinTheRadius) {
  std::vector<glm::vec3> points;
  std::vector<uint32_t> segment_points;
  for (int k = 0; k <= 40; ++k) points.push_back({0.5f * k, std::sin(0.3f * k), 0.0f});
  for (uint32_t k = 0; k < 40; ++k) segment_points.push_back(k);
  const TubeBvh bvh({points, segment_points, 0.4f, {}});
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> U(-1.5f, 1.5f);
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 x(10.0f + 7.0f * U(rng), U(rng), U(rng) * 0.5f);
    auto distance = [&](uint32_t k) {
      const glm::vec3 a = points[k], ba = points[k + 1] - a;
      const float u = std::clamp(glm::dot(x - a, ba) / glm::dot(ba, ba), 0.0f, 1.0f);
      return glm::length(x - (a + u * ba));
    };
    float best = 1e9f;
    uint32_t nearest = 0;
    for (uint32_t k = 0; k < 40; ++k)
      if (const float d = distance(k); d < best) best = d, nearest = k;
    TubeHit where;
    ASSERT_EQ(bvh.contains(x, &where), best <= 0.4f) << "point " << i;
    if (best <= 0.4f) {
      // Nearest to a shared vertex, two segments tie up to rounding, which differs with and
      // without FMA contraction: either is the answer.
      if (where.segment != nearest) {
        EXPECT_NEAR(distance(where.segment), best, 1e-6f);
      }
      EXPECT_NEAR(glm::length(where.normal), best, 1e-5f);
    }
  }
}

TEST(TubeBvh, DegenerateInputsBuildAndAnswer) {
  // 5,000 copies of one streamline (every box and centre the same: no split helps), repeated
  // points (segments of no length), and a tube far from the origin.
  std::vector<glm::vec3> points;
  std::vector<uint32_t> segment_points;
  for (int copy = 0; copy < 5000; ++copy) {
    const uint32_t first = static_cast<uint32_t>(points.size());
    for (glm::vec3 p : {glm::vec3(0, 0, 0), glm::vec3(0, 0, 0), glm::vec3(1, 0, 0),
                        glm::vec3(2, 0, 0), glm::vec3(2, 0, 0)})
      points.push_back(p);
    for (uint32_t k = 0; k < 4; ++k) segment_points.push_back(first + k);
  }
  const uint32_t far = static_cast<uint32_t>(points.size());
  points.push_back({1e6f, 0, 0});
  points.push_back({1e6f + 1, 0, 0});
  segment_points.push_back(far);
  const TubeBvh bvh({points, segment_points, 0.25f, {}});
  std::vector<TubeHit> hits(16);
  // Across the copies' tube at x = 1: each copy is a tube of its own, entered and left.
  const Ray across{{1.0f, 0.0f, -10.0f}, {0.0f, 0.0f, 1.0f}};
  ASSERT_EQ(bvh.nearest_hits(across, 0.0f, 1e9f, hits), 16u);
  for (const TubeHit& h : hits) EXPECT_NEAR(h.t, h.normal.z < 0 ? 9.75f : 10.25f, 1e-4f);
  // Along the axis, through the repeated points: one entry and one exit per copy.
  const Ray along{{-5.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}};
  ASSERT_EQ(bvh.nearest_hits(along, 0.0f, 1e9f, hits), 16u);
  for (const TubeHit& h : hits) EXPECT_NEAR(h.t, h.normal.x < 0 ? 4.75f : 7.25f, 1e-4f);
  // The far tube: found at its distance, within float's precision there.
  const Ray to_far{{1e6f + 0.5f, 0.0f, -10.0f}, {0.0f, 0.0f, 1.0f}};
  ASSERT_EQ(bvh.nearest_hits(to_far, 0.0f, 1e9f, hits), 2u);
  EXPECT_NEAR(hits[0].t, 9.75f, 0.1f);
  EXPECT_TRUE(bvh.contains({1.5f, 0.2f, 0.0f}));
  EXPECT_FALSE(bvh.contains({1.5f, 0.3f, 0.0f}));
}

}  // namespace
}  // namespace imx
