#include "measure/planar_region.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"

namespace imx {
namespace {

// A unit vector perpendicular to unit n: the world axis least along n, made perpendicular.
glm::dvec3 perpendicular(const glm::dvec3& n) {
  const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
  return glm::normalize(a - glm::dot(a, n) * n);
}

}  // namespace

PlanarRegion PlanarRegion::of(const Annotation& a) {
  PlanarRegion r;
  const std::vector<glm::dvec3>& p = a.points;
  if (a.kind == AnnotationKind::ellipse && p.size() == 3) {
    r.ellipse_ = true;
    r.origin_ = p[0];
    r.normal_ = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
    r.u_ = glm::normalize(p[1] - p[0]);
    r.v_ = glm::cross(r.normal_, r.u_);
    r.a_ = r.in_plane(p[1]);
    r.b_ = r.in_plane(p[2]);
    r.area_ = std::numbers::pi * std::abs(r.a_.x * r.b_.y - r.a_.y * r.b_.x);
    // The box of c + a cos θ + b sin θ: ±sqrt(a_i² + b_i²) along each axis.
    const glm::dvec2 half(std::hypot(r.a_.x, r.b_.x), std::hypot(r.a_.y, r.b_.y));
    r.lo_ = -half;
    r.hi_ = half;
    return r;
  }
  if (a.kind != AnnotationKind::polygon || p.size() < 3)
    throw Error(fmt::format("a {} with {} points is not a region (an ellipse or a polygon is)",
                            annotation_kind_name(a.kind), p.size()));
  glm::dvec3 n(0.0), centroid(0.0);
  for (size_t i = 0; i < p.size(); ++i) {
    n += glm::cross(p[i], p[(i + 1) % p.size()]);  // Newell's normal
    centroid += p[i] / static_cast<double>(p.size());
  }
  r.origin_ = centroid;
  r.normal_ = glm::normalize(n);
  r.u_ = perpendicular(r.normal_);
  r.v_ = glm::cross(r.normal_, r.u_);
  r.lo_ = glm::dvec2(INFINITY);
  r.hi_ = glm::dvec2(-INFINITY);
  double twice = 0.0;
  for (const glm::dvec3& c : p) r.corners_.push_back(r.in_plane(c));
  for (size_t i = 0; i < r.corners_.size(); ++i) {
    const glm::dvec2 q = r.corners_[i], s = r.corners_[(i + 1) % r.corners_.size()];
    twice += q.x * s.y - q.y * s.x;
    r.lo_ = glm::min(r.lo_, q);
    r.hi_ = glm::max(r.hi_, q);
  }
  r.area_ = 0.5 * std::abs(twice);
  return r;
}

glm::dvec2 PlanarRegion::in_plane(const glm::dvec3& p) const {
  const glm::dvec3 d = p - origin_;
  return {glm::dot(d, u_), glm::dot(d, v_)};
}

bool PlanarRegion::contains(const glm::dvec2& q) const {
  if (ellipse_) {
    // q = s a + t b: Cramer's rule on the 2x2 system.
    const double det = a_.x * b_.y - a_.y * b_.x;
    const double s = (q.x * b_.y - q.y * b_.x) / det;
    const double t = (a_.x * q.y - a_.y * q.x) / det;
    return s * s + t * t <= 1.0;
  }
  bool inside = false;
  for (size_t i = 0, j = corners_.size() - 1; i < corners_.size(); j = i++) {
    const glm::dvec2 a = corners_[i], b = corners_[j];
    // A crossing of the ray from q towards +u; half-open in v so that a vertex counts once.
    if ((a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y))
      inside = !inside;
  }
  return inside;
}

}  // namespace imx
