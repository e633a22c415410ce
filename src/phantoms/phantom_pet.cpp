#include <cmath>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

#include "phantoms/phantom_fields.hpp"
#include "phantoms/phantom_head.hpp"
#include "phantoms/phantoms.hpp"

namespace imx::detail {

namespace {

struct HotSpot {
  glm::dvec3 centre;  // mm, inside the brain
  double sigma;       // mm
  double peak;        // added to the brain's uptake of 2
};

constexpr HotSpot kHotSpots[3] = {{{25.0, -30.0, 30.0}, 7.0, 8.0},
                                  {{-30.0, 20.0, 10.0}, 8.0, 6.0},
                                  {{10.0, 40.0, -25.0}, 6.0, 10.0}};

double pet_value(const glm::dvec3& p, double h) {
  double v = inside(ellipsoid_distance(p, head::kCentre, head::kSkin), h);
  v += inside(ellipsoid_distance(p, head::kCentre, head::kSkullInner), h);
  for (const HotSpot& s : kHotSpots) {
    glm::dvec3 d = p - s.centre;
    v += s.peak * std::exp(-glm::dot(d, d) / (2.0 * s.sigma * s.sigma));
  }
  return v;
}

}  // namespace

Phantom pet_phantom(int size) {
  // A quarter of the resolution on the same field of view as ct-head, isotropic voxels.
  int n = std::max(8, size / 4);
  double s = head::kFieldOfView.y / n;
  glm::ivec3 dims(voxels_for(head::kFieldOfView.x, s), n, voxels_for(head::kFieldOfView.z, s));
  // Tilted like a scan from another machine: 10 degrees about z, then 5 about x.
  constexpr double deg = std::numbers::pi / 180.0;
  glm::dmat3 rotation = glm::dmat3(glm::rotate(glm::dmat4(1.0), 10.0 * deg, {0.0, 0.0, 1.0})) *
                        glm::dmat3(glm::rotate(glm::dmat4(1.0), 5.0 * deg, {1.0, 0.0, 0.0}));
  return field_phantom<float>(dims, centred_grid(dims, glm::dvec3(s), rotation),
                              [s](const glm::dvec3& p) { return pet_value(p, s); });
}

}  // namespace imx::detail
