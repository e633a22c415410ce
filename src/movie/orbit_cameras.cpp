#include "movie/orbit_cameras.hpp"

#include <cmath>

#include <glm/geometric.hpp>

namespace imx {

std::vector<Camera> orbit_cameras(const Camera& camera, int frames, double degrees) {
  const glm::dvec3 axis = glm::normalize(camera.up);
  const glm::dvec3 offset = camera.eye - camera.target;
  std::vector<Camera> cameras;
  for (int n = 0; n < frames; ++n) {
    const double a = degrees * M_PI / 180.0 * n / frames;
    // Rodrigues: the offset turned by a about the axis.
    const glm::dvec3 turned = offset * std::cos(a) + glm::cross(axis, offset) * std::sin(a) +
                              axis * glm::dot(axis, offset) * (1.0 - std::cos(a));
    Camera c = camera;
    c.eye = camera.target + turned;
    c.up = axis;
    cameras.push_back(c);
  }
  return cameras;
}

}  // namespace imx
