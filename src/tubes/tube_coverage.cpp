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

// What a candidate of the padded geometry (an entry into a padded tube) makes: the true tube's
// entry and exit, or both at the ray's closest approach to the axis when it passes the tube,
// and the part of the pixel covered (0: none, make no fragment).
struct CoveredCrossing {
  float coverage = 0.0f;
  TubeHit entry, exit;
};

// The points of a candidate's segment and its neighbours: from the run the hierarchy has at hand
// (in cache, having just been tested) while they lie in it, else from the streamlines.
class NeighbourPoints {
 public:
  NeighbourPoints(const TubeGeometry& g, const std::vector<glm::vec3>& points,
                  const TubeRunPoints& run)
      : g_(g), points_(points), run_(run) {}
  // Where `segment`'s points are, or null when `segment` is not joined to `from` (its neighbour
  // by one, already known to be of the object).
  const glm::vec3* joined(uint32_t from, uint32_t segment) const {
    const int64_t j = static_cast<int64_t>(segment) - run_.first_segment;
    const int64_t i = static_cast<int64_t>(from) - run_.first_segment;
    const int64_t n = run_.segments;
    if (j >= 0 && j < n) return run_.points + j;
    if (i >= 0 && i < n) {  // one past the run's ends: its joins say
      if (j < 0) return run_.joins & 1 ? run_.points - 1 : nullptr;
      return run_.joins & 2 ? run_.points + n : nullptr;
    }
    const uint32_t q = g_.first_point(segment), p = g_.first_point(from);
    return q + 1 == p || p + 1 == q ? points_.data() + q : nullptr;
  }
  // A segment's first point (the second follows it).
  const glm::vec3* of(uint32_t segment) const {
    const int64_t j = static_cast<int64_t>(segment) - run_.first_segment;
    return j >= 0 && j < run_.segments ? run_.points + j : points_.data() + g_.first_point(segment);
  }

 private:
  const TubeGeometry& g_;
  const std::vector<glm::vec3>& points_;
  const TubeRunPoints& run_;
};

CoveredCrossing covered_crossing(const TubeLook& look, const Ray& ray, const TubeHit& candidate,
                                 const TubeRunPoints& run) {
  CoveredCrossing out;
  if (glm::dot(candidate.normal, ray.dir) >= 0.0f) return out;  // the padded tube's exit
  const TubeGeometry& g = *look.geometry;
  const NeighbourPoints at(g, look.object->streamlines->points, run);
  const float radius = g.radius(), reach = radius + g.pad();
  // Joined segments share one padded surface: the ray may pass nearest to a neighbour of the
  // segment it entered by, so look along the streamline while its segments stay within reach.
  // The round tube is the union of its segments' capsules: it spans from the first capsule
  // entry to the last exit.
  uint32_t best = candidate.segment;
  const glm::vec3* best_points = at.of(best);
  Approach a = closest_approach(ray, best_points[0], best_points[1]);
  float t_in = INFINITY, t_out = -INFINITY;
  const glm::vec3 *in = best_points, *out_points = best_points;
  // `distance`: the segment's from the ray; a capsule farther than its radius is missed.
  auto span_of = [&](const glm::vec3* p, float distance) {
    if (!(distance <= radius)) return;
    const CapsuleSpan c = capsule_span(ray, p[0], p[1], radius);
    if (!c.hit) return;
    if (c.t_in < t_in) t_in = c.t_in, in = p;
    if (c.t_out > t_out) t_out = c.t_out, out_points = p;
  };
  span_of(best_points, a.distance);
  for (const int step : {1, -1}) {
    uint32_t segment = candidate.segment;
    for (int k = 0; k < kNeighbourWalk; ++k) {
      const int64_t next = static_cast<int64_t>(segment) + step;
      if (next < 0 || static_cast<size_t>(next) >= g.segment_count()) break;
      const glm::vec3* p = at.joined(segment, static_cast<uint32_t>(next));
      if (!p) break;  // another streamline
      const Approach b = closest_approach(ray, p[0], p[1]);
      if (!(b.distance < reach)) break;
      segment = static_cast<uint32_t>(next);
      span_of(p, b.distance);
      if (b.distance < a.distance) a = b, best = segment, best_points = p;
    }
  }
  const float footprint = look.footprint_at_0 + look.footprint_per_mm * std::max(a.t, 0.0f);
  out.coverage = tube_coverage(radius, a.distance, footprint);
  if (!(out.coverage > 0.0f)) return out;
  // Through the tube: its entry and exit; past it: both at the closest approach.
  if (!(t_in <= t_out)) t_in = t_out = a.t, in = out_points = best_points;
  for (TubeHit* h : {&out.entry, &out.exit}) {
    const bool entry = h == &out.entry;
    const glm::vec3* p = entry ? in : out_points;
    h->segment = best;
    h->u = a.u;
    h->t = entry ? t_in : t_out;
    h->normal = radial(ray.at(h->t), p[0], p[1]);
  }
  return out;
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
  // Rounded up to a step of 2^(1/8), at most 9% wider than asked: a padded tube's every pixel
  // is a candidate, so the hierarchy is kept about as tight as coverage allows.
  return std::exp2(std::ceil(8.0f * std::log2(0.5f * widest_footprint)) / 8.0f);
}

float silhouette_pad(const CameraModel& camera, const StreamlineObject& object) {
  return coverable(object) ? silhouette_pad(widest_footprint(camera, object)) : 0.0f;
}

void enable_silhouette_aa(TubeLook& look, float footprint_at_0, float footprint_per_mm) {
  if (!look.geometry || look.geometry->is_connectome()) return;
  look.silhouette_aa = true;
  look.footprint_at_0 = footprint_at_0;
  look.footprint_per_mm = footprint_per_mm;
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

CoveredGathering::CoveredGathering(const TubeLook& look, const Ray& ray, float lo, float hi,
                                   float t_min, float let_through, float bound)
    : look_(look), ray_(ray), lo_(lo), hi_(hi), before_(let_through), bound_(bound) {
  this->t_min = t_min;
  reach = hi;  // a candidate's fragments lie at or behind its padded entry
}

void CoveredGathering::add(const TubeHit& candidate, const TubeRunPoints& run) {
  const CoveredCrossing c = covered_crossing(look_, ray_, candidate, run);
  if (!(c.coverage > 0.0f)) return;
  auto kept = [&](const TubeHit& h) { return h.t >= lo_ && h.t <= hi_ && h.t < cut_t_; };
  const bool entry = kept(c.entry), exit = kept(c.exit);
  if (!entry && !exit) return;
  if (candidate_count_ == kMaxCandidates) drop_candidate(kMaxCandidates - 1);
  size_t k = candidate_count_++;
  for (; k > 0 && candidates_[k - 1].t > candidate.t; --k) candidates_[k] = candidates_[k - 1];
  candidates_[k] = {candidate.t, next_id_};
  const float alpha =
      tube_fragment_alpha(c.coverage * tube_crossing_opacity(look_, c.entry.segment));
  for (const TubeHit* h : {entry ? &c.entry : nullptr, exit ? &c.exit : nullptr}) {
    if (!h) continue;
    size_t j = count_++;
    for (; j > 0 && fragments_[j - 1].t > h->t; --j) fragments_[j] = fragments_[j - 1];
    fragments_[j] = {h->t,      c.coverage, alpha,    h->u,
                     h->normal, h->segment, next_id_, h == &c.entry ? 1u : 0u};
    product_ *= 1.0f - alpha;
  }
  ++next_id_;
  if (before_ * product_ < bound_) cut();
  if (candidate_count_ == kMaxCandidates)
    reach = std::min(reach, candidates_[kMaxCandidates - 1].t);
}

void CoveredGathering::drop_candidate(size_t k) {
  const uint32_t id = candidates_[k].id;
  for (; k + 1 < candidate_count_; ++k) candidates_[k] = candidates_[k + 1];
  --candidate_count_;
  size_t kept = 0;
  product_ = 1.0f;
  for (size_t j = 0; j < count_; ++j)
    if (fragments_[j].candidate != id) {
      product_ *= 1.0f - fragments_[j].alpha;
      fragments_[kept++] = fragments_[j];
    }
  count_ = kept;
}

void CoveredGathering::cut() {
  float through = before_;
  for (size_t j = 0; j < count_; ++j) {
    through *= 1.0f - fragments_[j].alpha;
    if (through < bound_) {
      count_ = j + 1;
      cut_t_ = fragments_[j].t;
      break;
    }
  }
  product_ = 1.0f;
  for (size_t j = 0; j < count_; ++j) product_ *= 1.0f - fragments_[j].alpha;
  // Candidates entering behind the cut have no fragment left in front of it.
  while (candidate_count_ > 0 && candidates_[candidate_count_ - 1].t >= cut_t_) --candidate_count_;
  reach = std::min(reach, cut_t_);
}

bool CoveredGathering::truncated() const {
  return candidate_count_ == kMaxCandidates && candidates_[kMaxCandidates - 1].t < cut_t_;
}

float CoveredGathering::let_through_before(float t) const {
  float through = before_;
  for (size_t j = 0; j < count_ && fragments_[j].t <= t; ++j) through *= 1.0f - fragments_[j].alpha;
  return through;
}
}  // namespace imx
