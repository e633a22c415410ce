#include <algorithm>
#include <cmath>

#include "phantoms/phantom_fields.hpp"
#include "phantoms/phantom_head.hpp"
#include "phantoms/phantoms.hpp"

namespace imx::detail {

namespace {

// Hounsfield units of the tissues.
constexpr double kAir = -1000.0, kSoftTissue = 40.0, kFat = -50.0, kCorticalBone = 1500.0,
                 kDiploeBone = 700.0, kVertebra = 900.0, kCsf = 8.0, kBrainTissue = 30.0,
                 kVentricle = 5.0, kEyeball = 10.0;

constexpr double kOrbitRadius = 16.0, kEyeRadius = 12.0;
const glm::dvec3 kEyes[2] = {{32.0, -70.0, -8.0}, {-32.0, -70.0, -8.0}};

double elliptic_cylinder_distance(const glm::dvec3& p, const glm::dvec2& centre,
                                  const glm::dvec2& radii) {
  return ellipsoid_distance(glm::dvec3(p.x, p.y, 0.0), glm::dvec3(centre, 0.0),
                            glm::dvec3(radii, 1.0));
}

// HU at world point p; h is the width of the soft edges (one voxel).
double ct_head_value(const glm::dvec3& p, double h) {
  using namespace head;
  double v = kAir;
  // Each layer overwrites what lies inside it, blended by its partial-volume fraction.
  auto layer = [&](double distance, double value) { v += inside(distance, h) * (value - v); };

  double nose = ellipsoid_distance(p, {0.0, -84.0, -22.0}, {9.0, 18.0, 22.0});
  double ears = std::min(ellipsoid_distance(p, {74.0, 6.0, -4.0}, {6.0, 12.0, 20.0}),
                         ellipsoid_distance(p, {-74.0, 6.0, -4.0}, {6.0, 12.0, 20.0}));
  double neck = std::max(elliptic_cylinder_distance(p, {0.0, 14.0}, {50.0, 54.0}), p.z + 50.0);
  double skin = std::min({ellipsoid_distance(p, kCentre, kSkin), nose, ears, neck});
  if (skin >= 0.5 * h) return kAir;  // outside the head every later layer is empty too
  double orbit_centre = std::min(glm::length(p - kEyes[0]), glm::length(p - kEyes[1]));

  layer(skin, kSoftTissue);
  layer(ellipsoid_distance(p, kCentre, kSkullOuter), kCorticalBone);
  layer(ellipsoid_distance(p, kCentre, kDiploe), kDiploeBone);
  layer(ellipsoid_distance(p, kCentre, kInnerTable), kCorticalBone);
  // CSF and brain keep clear of the orbits, leaving a bony orbital roof.
  layer(std::max(ellipsoid_distance(p, kCentre, kSkullInner), kOrbitRadius + 4.0 - orbit_centre),
        kCsf);
  layer(std::max(ellipsoid_distance(p, kCentre, kBrain), kOrbitRadius + 6.0 - orbit_centre),
        kBrainTissue);
  layer(std::min(ellipsoid_distance(p, {9.0, 2.0, 15.0}, {4.0, 16.0, 9.0}),
                 ellipsoid_distance(p, {-9.0, 2.0, 15.0}, {4.0, 16.0, 9.0})),
        kVentricle);
  // Orbits cut the skull in front (orbital fat), each holding an eyeball.
  layer(std::max(orbit_centre - kOrbitRadius, skin), kFat);
  layer(std::max(orbit_centre - kEyeRadius, skin), kEyeball);
  // Cervical spine inside the neck, up to the skull base.
  layer(std::max(elliptic_cylinder_distance(p, {0.0, 28.0}, {10.0, 10.0}), p.z + 80.0), kVertebra);
  return v;
}

}  // namespace

Phantom ct_head_phantom(int size) {
  // In-plane 0.9 mm and 1.2 mm slices at size 256; the field of view stays the same.
  double in_plane = head::kFieldOfView.y / size;
  glm::dvec3 spacing(in_plane, in_plane, in_plane * 4.0 / 3.0);
  glm::ivec3 dims(voxels_for(head::kFieldOfView.x, spacing.x), size,
                  voxels_for(head::kFieldOfView.z, spacing.z));
  double h = spacing.z;
  return field_phantom<int16_t>(dims, centred_grid(dims, spacing),
                                [h](const glm::dvec3& p) { return ct_head_value(p, h); });
}

}  // namespace imx::detail
