#include "tubes/tube_clip.hpp"

#include <limits>

#include <glm/glm.hpp>

namespace imx {

TubeClip::TubeClip(const StreamlineObject& object) {
  for (const ClipPlane& p : object.clip_planes)
    planes_.push_back({glm::vec3(p.point), glm::normalize(glm::vec3(p.normal))});
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

}  // namespace imx
