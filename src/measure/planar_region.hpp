// A flat region of world space, an ellipse or a polygon ROI (docs/viewer.md, "Measurements"): its
// plane, its area and which points of the plane it holds.
#pragma once
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "intermix/scene.hpp"
#include "scene/annotation.hpp"

namespace imx {

class PlanarRegion {
 public:
  // The region of an ellipse or polygon annotation (one the scene parser accepted: an ellipse's
  // semi-axes not parallel, a polygon flat and of some area); throws imx::Error for a ruler or
  // an angle.
  static PlanarRegion of(const Annotation& a);

  glm::dvec3 origin() const { return origin_; }
  glm::dvec3 normal() const { return normal_; }  // unit
  // An orthonormal basis of the plane: (u, v, normal) is right-handed.
  glm::dvec3 u() const { return u_; }
  glm::dvec3 v() const { return v_; }
  // A world point's coordinates in the plane, (u, v) from the origin (its offset along the
  // normal ignored).
  glm::dvec2 in_plane(const glm::dvec3& p) const;
  // Whether in-plane point q lies in the region: s² + t² <= 1 for an ellipse's parameters, the
  // even-odd rule for a polygon (a self-crossing polygon holds what it winds round an odd number
  // of times).
  bool contains(const glm::dvec2& q) const;
  double area_mm2() const { return area_; }  // a self-crossing polygon: its shoelace magnitude
  // The in-plane box [lo, hi] that holds the region.
  glm::dvec2 lo() const { return lo_; }
  glm::dvec2 hi() const { return hi_; }

 private:
  bool ellipse_ = false;
  glm::dvec3 origin_{0.0}, normal_{0.0, 0.0, 1.0}, u_{1.0, 0.0, 0.0}, v_{0.0, 1.0, 0.0};
  glm::dvec2 a_{0.0}, b_{0.0};       // an ellipse's semi-axes in the plane
  std::vector<glm::dvec2> corners_;  // a polygon's, in the plane
  double area_ = 0.0;
  glm::dvec2 lo_{0.0}, hi_{0.0};
};

}  // namespace imx
