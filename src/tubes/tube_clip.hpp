// TubeClip: a streamline object's clip planes and the part of a ray they keep (where a plane
// cuts a tube, TubeGeometry::contains finds the tube for its cap).
#pragma once
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "core/ray.hpp"
#include "intermix/scene.hpp"

namespace imx {

class TubeClip {
 public:
  // The part of a ray in [0, inf) that every plane keeps: lo < t < hi, with the plane that sets
  // each end (-1: the ray's start, or no end).
  struct Span {
    float lo = 0.0f, hi = 0.0f;
    int lo_plane = -1, hi_plane = -1;
  };

  explicit TubeClip(const StreamlineObject& object);  // its clip_planes

  Span kept(const Ray& ray) const;

  // The plane's unit normal, toward the side it keeps.
  const glm::vec3& normal(int plane) const { return planes_[plane].normal; }
  size_t plane_count() const { return planes_.size(); }

 private:
  struct Plane {
    glm::vec3 point{0.0f}, normal{0.0f};
  };
  std::vector<Plane> planes_;
};

}  // namespace imx
