// The tube hierarchy (src/tubes/tube_bvh.*) on fuzzed geometry. Byte 0 sets the radius
// (0.01 + byte / 16 mm); then 13-byte records: a control byte (bit 0: a new streamline starts
// here) and a point as three float32, non-finite coordinates read as 0 (the readers refuse
// them; every finite magnitude may come). Rays start near the points and aim at others. The
// crossings must come sorted, within the asked range, each naming a segment there is; a visitor
// that lowers its reach to each crossing must be given the nearest, with its run's points, to
// float precision, within 100 m: a crossing of a long thin segment is off by up to about 1e-3
// of its length (0.03 mm for 97 mm at radius 0.01; streamlines step 0.1-2 mm), so the two may
// pick different ones of crossings that close; at kilometres nothing is that precise.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <glm/glm.hpp>

#include "harness.hpp"
#include "tubes/tube_bvh.hpp"

namespace {

// Keeps the nearest crossing it is given; each must lie in range and name its run's segment.
struct Nearest final : imx::TubeHitVisitor {
  size_t segments = 0;
  float nearest = INFINITY;
  void add(const imx::TubeHit& hit, const imx::TubeRunPoints& run) override {
    if (!(hit.t > t_min && hit.t < reach)) __builtin_trap();
    if (hit.segment >= segments || hit.segment - run.first_segment >= run.segments)
      __builtin_trap();
    nearest = std::min(nearest, hit.t);
    reach = hit.t;
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const float radius = 0.01f + data[0] / 16.0f;
  std::vector<glm::vec3> points;
  std::vector<uint32_t> segment_points;
  for (size_t at = 1; at + 13 <= size && points.size() < 4096; at += 13) {
    float v[3];
    std::memcpy(v, data + at + 1, sizeof(v));
    for (float& x : v)
      if (!std::isfinite(x)) x = 0.0f;
    const bool starts = (data[at] & 1) || points.empty();
    if (!starts) segment_points.push_back(static_cast<uint32_t>(points.size() - 1));
    points.push_back({v[0], v[1], v[2]});
  }
  const imx::TubeBvh bvh({points, segment_points, radius, {}});
  float longest = 0.0f, farthest = 0.0f;  // how far apart crossings must be to be told apart
  for (uint32_t q : segment_points)
    longest = std::max(longest, glm::length(points[q + 1] - points[q]));
  for (const glm::vec3& p : points)
    farthest = std::max({farthest, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  std::vector<imx::TubeHit> hits(8);
  for (size_t i = 0; i + 1 < points.size() && i < 32; ++i) {
    const glm::vec3 origin = points[i] + glm::vec3(1.0f, 2.0f, 3.0f);
    const glm::vec3 to = points[(i * 7 + 1) % points.size()] - origin;
    const float length = glm::length(to);
    if (!(length > 0.0f) || !std::isfinite(length)) continue;
    const imx::Ray ray{origin, to / length};
    const float t_min = (data[0] & 1) ? 0.5f : 0.0f, t_max = 1e30f;
    const size_t n = bvh.nearest_hits(ray, t_min, t_max, hits);
    if (n > hits.size()) __builtin_trap();
    for (size_t k = 0; k < n; ++k) {
      if (!(hits[k].t > t_min && hits[k].t < t_max)) __builtin_trap();
      if (k > 0 && hits[k].t < hits[k - 1].t) __builtin_trap();
      if (hits[k].segment >= segment_points.size()) __builtin_trap();
    }
    Nearest visitor;
    visitor.segments = segment_points.size();
    visitor.t_min = t_min;
    visitor.reach = t_max;
    bvh.visit_hits(ray, visitor);
    if ((n > 0) != std::isfinite(visitor.nearest)) __builtin_trap();
    if (n > 0 && farthest <= 1e5f &&
        !(std::abs(visitor.nearest - hits[0].t) <=
          1e-3f * (1.0f + longest) + 1e-4f * std::abs(hits[0].t)))
      __builtin_trap();
    imx::TubeHit where;
    if (bvh.contains(points[i], &where) && where.segment >= segment_points.size()) __builtin_trap();
  }
  return 0;
}
