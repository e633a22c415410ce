// Ray: an origin and a unit direction; depth t is the distance from the origin in mm (SPEC §1).
#pragma once
#include <glm/vec3.hpp>

namespace imx {

struct Ray {
  glm::vec3 origin{0.0f};
  glm::vec3 dir{0.0f, 0.0f, 1.0f};
  glm::vec3 at(float t) const { return origin + t * dir; }
};

}  // namespace imx
