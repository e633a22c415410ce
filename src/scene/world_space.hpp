// A scene file's world space ("space": "LPS" or "RAS" at its top): intermix works in LPS, so
// points, directions and inline transforms a RAS scene gives have x and y negated as they are
// read (a rotation by 180 degrees about z, which keeps handedness and winding).
#pragma once
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "intermix/io.hpp"

namespace imx::scene_json {

// RAS to LPS and back: diag(-1, -1, 1, 1).
inline glm::dmat4 ras_lps_flip() {
  glm::dmat4 m(1.0);
  m[0][0] = m[1][1] = -1.0;
  return m;
}

// A point or direction the scene gives in `space`, in LPS.
inline glm::dvec3 to_lps(const glm::dvec3& v, MeshSpace space) {
  return space == MeshSpace::ras ? glm::dvec3(-v.x, -v.y, v.z) : v;
}

}  // namespace imx::scene_json
