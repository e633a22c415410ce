#include "tubes/tube_coverage.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <glm/glm.hpp>

namespace imx {
namespace {

constexpr int kNeighbourWalk = 16;  // segments a covered crossing looks along each way
// The fewest hits an opaque covered object asks per query: each padded tube is an entry and an
// exit, and a few partly covering ones in front of a full one are common.
constexpr size_t kCoveredHitsPerQuery = 6;

// Where a ray passes closest to a segment's axis.
struct Approach {
  float t = 0.0f;         // along the ray
  float u = 0.0f;         // along the segment, 0..1
  float distance = 0.0f;  // from the axis
};

Approach closest_approach(const Ray& ray, const glm::vec3& p0, const glm::vec3& p1) {
  const glm::vec3 e = p1 - p0, w = ray.origin - p0;
  const float b = glm::dot(ray.dir, e), d = glm::dot(ray.dir, w);
  const glm::vec3 e_perp = e - b * ray.dir, w_perp = w - d * ray.dir;
  const float ee = glm::dot(e_perp, e_perp);
  Approach a;
  a.u = ee > 1e-12f ? std::clamp(glm::dot(w_perp, e_perp) / ee, 0.0f, 1.0f) : 0.0f;
  a.t = a.u * b - d;
  a.distance = glm::length(w_perp - a.u * e_perp);
  return a;
}

// Where a ray enters and leaves a capsule: the union of a cylinder and two spheres, all convex,
// so from the first piece's entry to the last one's exit.
struct CapsuleSpan {
  bool hit = false;
  float t_in = INFINITY, t_out = -INFINITY;
};

CapsuleSpan capsule_span(const Ray& ray, const glm::vec3& pa, const glm::vec3& pb, float r) {
  CapsuleSpan span;
  auto take = [&](float t0, float t1) {
    span.hit = true;
    span.t_in = std::min(span.t_in, t0);
    span.t_out = std::max(span.t_out, t1);
  };
  for (const glm::vec3& centre : {pa, pb}) {
    const glm::vec3 oc = ray.origin - centre;
    const float b = glm::dot(ray.dir, oc), h = b * b - (glm::dot(oc, oc) - r * r);
    if (h >= 0.0f) take(-b - std::sqrt(h), -b + std::sqrt(h));
  }
  const glm::vec3 ba = pb - pa, oa = ray.origin - pa;
  const float baba = glm::dot(ba, ba), bard = glm::dot(ba, ray.dir), baoa = glm::dot(ba, oa);
  const float a = baba - bard * bard;
  if (a > 1e-12f * baba && baba > 0.0f) {
    const float b = baba * glm::dot(ray.dir, oa) - baoa * bard;
    const float c = baba * glm::dot(oa, oa) - baoa * baoa - r * r * baba;
    const float h = b * b - a * c;
    if (h >= 0.0f) {
      const float t0 = (-b - std::sqrt(h)) / a, t1 = (-b + std::sqrt(h)) / a;
      const float y0 = baoa + t0 * bard, y1 = baoa + t1 * bard;
      if (y0 > 0.0f && y0 < baba) take(t0, t0);
      if (y1 > 0.0f && y1 < baba) take(t1, t1);
    }
  }
  return span;
}

// The outward normal (not unit length) of the segment's tube at a point near its surface.
glm::vec3 radial(const glm::vec3& point, const glm::vec3& p0, const glm::vec3& p1) {
  const glm::vec3 e = p1 - p0;
  const float length2 = glm::dot(e, e);
  const float u = length2 > 0.0f ? std::clamp(glm::dot(point - p0, e) / length2, 0.0f, 1.0f) : 0.0f;
  return point - (p0 + u * e);
}

// The widest pixel footprint (mm) over `object`'s tubes: at the point farthest from the eye,
// found with both cores (it is asked every frame, of millions of points).
float widest_footprint(const CameraModel& camera, const StreamlineObject& object) {
  if (!camera.perspective()) return static_cast<float>(camera.pixel_footprint(0.0));
  const std::vector<glm::vec3>& points = object.streamlines->points;
  if (points.empty()) return 0.0f;
  const glm::vec3 eye(camera.eye());
  const float far2 = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, points.size(), 1 << 16), 0.0f,
      [&](const tbb::blocked_range<size_t>& r, float farthest) {
        for (size_t k = r.begin(); k < r.end(); ++k) {
          const glm::vec3 d = points[k] - eye;
          farthest = std::max(farthest, glm::dot(d, d));
        }
        return farthest;
      },
      [](float a, float b) { return std::max(a, b); });
  return static_cast<float>(camera.pixel_footprint(std::sqrt(far2) + object.radius));
}

}  // namespace

bool tube_coverage_on(const RenderSettings& render, bool zslab_method) {
  if (render.tube_coverage == "on") return true;
  if (render.tube_coverage == "off") return false;
  return zslab_method;
}

bool coverable(const StreamlineObject& object) {
  return !object.connectome && object.streamlines;
}

float silhouette_pad(float widest_footprint) {
  if (!(widest_footprint > 0.0f)) return 0.0f;
  return std::exp2(std::ceil(std::log2(0.5f * widest_footprint)));
}

float silhouette_pad(const CameraModel& camera, const StreamlineObject& object) {
  return coverable(object) ? silhouette_pad(widest_footprint(camera, object)) : 0.0f;
}

void enable_silhouette_aa(TubeLook& look, float footprint_at_0, float footprint_per_mm) {
  if (!look.geometry || look.geometry->is_connectome()) return;
  look.silhouette_aa = true;
  look.footprint_at_0 = footprint_at_0;
  look.footprint_per_mm = footprint_per_mm;
  look.hits_per_query = std::max(look.hits_per_query, kCoveredHitsPerQuery);
}

void enable_silhouette_aa(TubeLook& look, const CameraModel& camera) {
  const auto at_0 = static_cast<float>(camera.pixel_footprint(0.0));
  enable_silhouette_aa(look, at_0, static_cast<float>(camera.pixel_footprint(1.0)) - at_0);
}

void hard_tubes_through_pad(TubeLook& look) {
  if (look.geometry && look.geometry->pad() > 0.0f) enable_silhouette_aa(look, 0.0f, 0.0f);
}

void share_footprint(TubeLook& look, size_t samples) {
  if (samples <= 1) return;
  const float share = 1.0f / std::sqrt(static_cast<float>(samples));
  look.footprint_at_0 *= share;
  look.footprint_per_mm *= share;
}

float tube_coverage(float radius, float distance, float footprint) {
  if (!(footprint > 0.0f)) return distance <= radius ? 1.0f : 0.0f;
  return std::clamp((radius + 0.5f * footprint - distance) / footprint, 0.0f, 1.0f);
}

size_t covered_fragments_needed(const StreamlineObject& object) {
  const size_t needed = tube_fragments_needed(object);
  return coverable(object) ? std::max(needed, kCoveredFragments) : needed;
}

CoveredCrossing covered_crossing(const TubeLook& look, const Ray& ray, const TubeHit& candidate) {
  CoveredCrossing out;
  if (glm::dot(candidate.normal, ray.dir) >= 0.0f) return out;  // the padded tube's exit
  const std::vector<glm::vec3>& points = look.object->streamlines->points;
  const TubeGeometry& g = *look.geometry;
  const float radius = g.radius(), reach = radius + g.pad();
  // Joined segments share one padded surface: the ray may pass nearest to a neighbour of the
  // segment it entered by, so look along the streamline while its segments stay within reach.
  // The round tube is the union of its segments' capsules: it spans from the first capsule
  // entry to the last exit.
  uint32_t best = candidate.segment;
  Approach a = closest_approach(ray, points[g.first_point(best)], points[g.first_point(best) + 1]);
  float t_in = INFINITY, t_out = -INFINITY;
  uint32_t seg_in = best, seg_out = best;
  // `distance`: the segment's from the ray; a capsule farther than its radius is missed.
  auto span_of = [&](uint32_t segment, float distance) {
    if (!(distance <= radius)) return;
    const uint32_t q = g.first_point(segment);
    const CapsuleSpan c = capsule_span(ray, points[q], points[q + 1], radius);
    if (!c.hit) return;
    if (c.t_in < t_in) t_in = c.t_in, seg_in = segment;
    if (c.t_out > t_out) t_out = c.t_out, seg_out = segment;
  };
  span_of(best, a.distance);
  for (const int step : {1, -1}) {
    uint32_t segment = candidate.segment;
    for (int k = 0; k < kNeighbourWalk; ++k) {
      const int64_t next = static_cast<int64_t>(segment) + step;
      if (next < 0 || static_cast<size_t>(next) >= g.segment_count()) break;
      const uint32_t q = g.first_point(static_cast<uint32_t>(next));
      if (q != g.first_point(segment) + step) break;  // another streamline
      const Approach b = closest_approach(ray, points[q], points[q + 1]);
      if (!(b.distance < reach)) break;
      segment = static_cast<uint32_t>(next);
      span_of(segment, b.distance);
      if (b.distance < a.distance) a = b, best = segment;
    }
  }
  const float footprint = look.footprint_at_0 + look.footprint_per_mm * std::max(a.t, 0.0f);
  out.coverage = tube_coverage(radius, a.distance, footprint);
  if (!(out.coverage > 0.0f)) return out;
  // Through the tube: its entry and exit; past it: both at the closest approach.
  if (!(t_in <= t_out)) t_in = t_out = a.t, seg_in = seg_out = best;
  for (TubeHit* h : {&out.entry, &out.exit}) {
    const bool entry = h == &out.entry;
    const uint32_t q = g.first_point(entry ? seg_in : seg_out);
    h->segment = best;
    h->u = a.u;
    h->t = entry ? t_in : t_out;
    h->normal = radial(ray.at(h->t), points[q], points[q + 1]);
  }
  return out;
}

void sort_covered_fragments(std::vector<Fragment>& out, size_t first) {
  // Insertion: a few dozen fragments, mostly in order already (an entry before its exit, and
  // a second sort after a cut finds all but the last query's in place).
  for (size_t k = first + 1; k < out.size(); ++k) {
    const Fragment f = out[k];
    size_t j = k;
    for (; j > first && f.t < out[j - 1].t; --j) out[j] = out[j - 1];
    out[j] = f;
  }
}

float cut_covered_fragments(std::vector<Fragment>& out, size_t first, float bound,
                            float& let_through) {
  sort_covered_fragments(out, first);
  float through = 1.0f;
  for (size_t k = first; k < out.size(); ++k) {
    through *= 1.0f - out[k].color.a;
    if (through < bound) {
      out.resize(k + 1);
      let_through = through;
      return out[k].t;
    }
  }
  let_through = through;
  return INFINITY;
}

}  // namespace imx
