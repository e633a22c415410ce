#include <algorithm>
#include <cmath>

#include "phantoms/phantom_fields.hpp"
#include "phantoms/phantoms.hpp"

namespace imx::detail {

Phantom cube_phantom(int size) {
  double s = 128.0 / size;  // a 128 mm grid: 1 mm voxels at size 128
  glm::ivec3 dims(size);
  glm::dvec3 half(0.3 * 128.0);
  return field_phantom<uint8_t>(dims, centred_grid(dims, glm::dvec3(s)), [=](const glm::dvec3& p) {
    return 255.0 * inside(box_distance(p, half), s);
  });
}

Phantom ellipsoid_phantom(int size) {
  // 0.8 mm voxels at size 128, unlike cube's 1 mm, on a grid shaped like the ellipsoid.
  double s = 102.4 / size;
  glm::ivec3 dims(size, voxels_for(76.8, s), voxels_for(83.2, s));
  glm::dvec3 radii(45.0, 30.0, 35.0);
  return field_phantom<uint8_t>(dims, centred_grid(dims, glm::dvec3(s)), [=](const glm::dvec3& p) {
    return 255.0 * inside(ellipsoid_distance(p, glm::dvec3(0.0), radii), s);
  });
}

Phantom shells_phantom(int size) {
  constexpr int kShells = 8;
  double s = 128.0 / size;
  double pitch = 0.44 * 128.0 / kShells;  // shell i is centred on radius pitch * (i + 1)
  // Walls two voxels thick, thinner only when the grid is too coarse to keep them apart.
  double thickness = std::min(2.0 * s, 0.5 * pitch);
  glm::ivec3 dims(size);
  return field_phantom<float>(dims, centred_grid(dims, glm::dvec3(s)), [=](const glm::dvec3& p) {
    double r = glm::length(p);
    int nearest = std::clamp(static_cast<int>(std::lround(r / pitch)) - 1, 0, kShells - 1);
    double v = 0.0;
    for (int i = std::max(0, nearest - 1); i <= std::min(kShells - 1, nearest + 1); ++i) {
      double wall = std::abs(r - pitch * (i + 1)) - 0.5 * thickness;
      v = std::max(v, 10.0 * (i + 1) * inside(wall, s));
    }
    return v;
  });
}

Phantom sphere_phantom(int size) {
  double s = 128.0 / size;
  double radius = 0.35 * 128.0;
  glm::ivec3 dims(size);
  return field_phantom<float>(dims, centred_grid(dims, glm::dvec3(s)),
                              [=](const glm::dvec3& p) { return radius - glm::length(p); });
}

}  // namespace imx::detail
