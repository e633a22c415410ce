#include "tubes/tube_clip.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <glm/glm.hpp>

namespace imx {
namespace {

constexpr int kMaxCellsPerSide = 1024;  // a cap test reads one cell of at most 1024² per plane

// Two unit vectors spanning the plane of unit normal n.
void plane_basis(const glm::vec3& n, glm::vec3& e1, glm::vec3& e2) {
  const glm::vec3 other = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  e1 = glm::normalize(glm::cross(n, other));
  e2 = glm::cross(n, e1);
}

// A segment whose tube meets the plane, and the box in plane coordinates that holds the meeting.
struct Candidate {
  uint32_t segment;
  glm::vec2 low, high;
};

// Whether the tube of radius r around segment ab meets the plane through `point` of unit
// normal n; if so c's box holds where, in the plane's (e1, e2) coordinates.
bool footprint(const glm::vec3& a, const glm::vec3& b, float r, const glm::vec3& point,
               const glm::vec3& n, const glm::vec3& e1, const glm::vec3& e2, Candidate& c) {
  const float da = glm::dot(a - point, n), db = glm::dot(b - point, n);
  if (std::min(da, db) > r || std::max(da, db) < -r) return false;
  // A point of the plane within r of the segment is within r of its part in the slab |d| <= r,
  // and so within r of that part's projection.
  float t0 = 0.0f, t1 = 1.0f;
  if (da != db) {
    const float ta = (-r - da) / (db - da), tb = (r - da) / (db - da);
    t0 = std::max(0.0f, std::min(ta, tb));
    t1 = std::min(1.0f, std::max(ta, tb));
  }
  const glm::vec3 pa = a + t0 * (b - a) - point, pb = a + t1 * (b - a) - point;
  const glm::vec2 qa(glm::dot(pa, e1), glm::dot(pa, e2)), qb(glm::dot(pb, e1), glm::dot(pb, e2));
  c.low = glm::min(qa, qb) - r;
  c.high = glm::max(qa, qb) + r;
  return true;
}

}  // namespace

TubeClip::TubeClip(const StreamlineObject& object, const TubeGeometry& geometry)
    : streamlines_(object.streamlines.get()),
      geometry_(&geometry),
      radius_(static_cast<float>(object.radius)) {
  planes_.resize(object.clip_planes.size());
  for (size_t i = 0; i < planes_.size(); ++i) {
    Plane& p = planes_[i];
    p.point = glm::vec3(object.clip_planes[i].point);
    p.normal = glm::normalize(glm::vec3(object.clip_planes[i].normal));
    plane_basis(p.normal, p.e1, p.e2);
    build(p);
  }
}

void TubeClip::build(Plane& plane) const {
  const float r = radius_;
  const std::vector<glm::vec3>& points = streamlines_->points;
  // The scan over every segment is the cost (13 ms at 0.87 M segments on one core): in parallel.
  tbb::enumerable_thread_specific<std::vector<Candidate>> local;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, geometry_->segment_count(), 16384),
                    [&](const tbb::blocked_range<size_t>& range) {
                      std::vector<Candidate>& mine = local.local();
                      for (size_t s = range.begin(); s < range.end(); ++s) {
                        const uint32_t first = geometry_->first_point(static_cast<uint32_t>(s));
                        Candidate c{static_cast<uint32_t>(s), {}, {}};
                        if (footprint(points[first], points[first + 1], r, plane.point,
                                      plane.normal, plane.e1, plane.e2, c))
                          mine.push_back(c);
                      }
                    });
  std::vector<Candidate> found;
  for (const std::vector<Candidate>& part : local)
    found.insert(found.end(), part.begin(), part.end());
  // In segment order, whatever the threads did: ties between tubes resolve the same each frame.
  std::sort(found.begin(), found.end(),
            [](const Candidate& x, const Candidate& y) { return x.segment < y.segment; });
  glm::vec2 low(std::numeric_limits<float>::max()), high(-std::numeric_limits<float>::max());
  for (const Candidate& c : found) {
    low = glm::min(low, c.low);
    high = glm::max(high, c.high);
  }
  plane.segments = found.size();
  if (found.empty()) return;
  const glm::vec2 extent = high - low;
  plane.low = low;
  plane.cell =
      std::max({2.0f * r, extent.x / kMaxCellsPerSide, extent.y / kMaxCellsPerSide, 1e-6f});
  plane.nx = std::min(kMaxCellsPerSide, static_cast<int>(extent.x / plane.cell) + 1);
  plane.ny = std::min(kMaxCellsPerSide, static_cast<int>(extent.y / plane.cell) + 1);
  auto cell_of = [&](float v, float lo, int n) {
    return std::clamp(static_cast<int>((v - lo) / plane.cell), 0, n - 1);
  };
  plane.cell_start.assign(size_t(plane.nx) * plane.ny + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    for (const Candidate& c : found) {
      const int x0 = cell_of(c.low.x, low.x, plane.nx), x1 = cell_of(c.high.x, low.x, plane.nx);
      const int y0 = cell_of(c.low.y, low.y, plane.ny), y1 = cell_of(c.high.y, low.y, plane.ny);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const size_t cell = size_t(y) * plane.nx + x;
          if (pass == 0)
            ++plane.cell_start[cell + 1];
          else
            plane.items[plane.cell_start[cell]++] = c.segment;
        }
    }
    if (pass == 0) {
      for (size_t i = 1; i < plane.cell_start.size(); ++i)
        plane.cell_start[i] += plane.cell_start[i - 1];
      plane.items.resize(plane.cell_start.back());
    } else {  // the fill moved each start to its cell's end: shift back
      for (size_t i = plane.cell_start.size() - 1; i > 0; --i)
        plane.cell_start[i] = plane.cell_start[i - 1];
      plane.cell_start[0] = 0;
    }
  }
}

TubeClip::Span TubeClip::kept(const Ray& ray) const {
  Span s;
  s.hi = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < planes_.size(); ++i) {
    const Plane& p = planes_[i];
    const float d0 = glm::dot(ray.origin - p.point, p.normal);
    const float dd = glm::dot(ray.dir, p.normal);
    if (dd == 0.0f) {
      if (d0 < 0.0f) s.hi = s.lo;  // parallel, on the removed side: nothing kept
      continue;
    }
    const float t = -d0 / dd;
    if (dd > 0.0f && t > s.lo) {
      s.lo = t;
      s.lo_plane = static_cast<int>(i);
    } else if (dd < 0.0f && t < s.hi) {
      s.hi = t;
      s.hi_plane = static_cast<int>(i);
    }
  }
  return s;
}

bool TubeClip::inside(int plane, const glm::vec3& p, TubeHit* at) const {
  const Plane& pl = planes_[plane];
  if (pl.items.empty()) return false;
  const glm::vec3 rel = p - pl.point;
  const float x = (glm::dot(rel, pl.e1) - pl.low.x) / pl.cell;
  const float y = (glm::dot(rel, pl.e2) - pl.low.y) / pl.cell;
  if (!(x >= 0.0f && y >= 0.0f && x < float(pl.nx) && y < float(pl.ny))) return false;
  const size_t cell = size_t(y) * pl.nx + size_t(x);
  const std::vector<glm::vec3>& points = streamlines_->points;
  float best = radius_ * radius_;
  bool found = false;
  for (uint32_t k = pl.cell_start[cell]; k < pl.cell_start[cell + 1]; ++k) {
    const uint32_t s = pl.items[k];
    const uint32_t first = geometry_->first_point(s);
    const glm::vec3 a = points[first], ab = points[first + 1] - a;
    const float len2 = glm::dot(ab, ab);
    const float u = len2 > 0.0f ? std::clamp(glm::dot(p - a, ab) / len2, 0.0f, 1.0f) : 0.0f;
    const glm::vec3 off = p - (a + u * ab);
    const float d2 = glm::dot(off, off);
    if (d2 <= best) {
      best = d2;
      found = true;
      if (at) at->segment = s, at->u = u;
    }
  }
  return found;
}

size_t TubeClip::crossing_segments() const {
  size_t n = 0;
  for (const Plane& p : planes_) n += p.segments;
  return n;
}

}  // namespace imx
