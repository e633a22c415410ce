// Building blocks of the built-in phantoms: centred grids, signed distances, soft edges.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#include "core/parallel.hpp"
#include "intermix/volume.hpp"

namespace imx::detail {

// Index-to-world for a grid of `dims` voxels of `spacing` mm whose centre sits at the world
// origin, with the grid axes turned by `rotation`.
inline glm::dmat4 centred_grid(glm::ivec3 dims, glm::dvec3 spacing,
                               const glm::dmat3& rotation = glm::dmat3(1.0)) {
  glm::dmat3 linear =
      rotation * glm::dmat3(glm::dvec3(spacing.x, 0, 0), glm::dvec3(0, spacing.y, 0),
                            glm::dvec3(0, 0, spacing.z));
  glm::dvec3 centre_index = 0.5 * glm::dvec3(dims - 1);
  glm::dmat4 m(linear);
  m[3] = glm::dvec4(-(linear * centre_index), 1.0);
  return m;
}

// Voxels along an axis whose extent is `extent_mm` at `spacing` mm (at least 2).
inline int voxels_for(double extent_mm, double spacing) {
  return std::max(2, static_cast<int>(std::lround(extent_mm / spacing)));
}

// Fraction of a voxel of width `h` inside a surface at signed distance `d` (negative inside):
// a smoothstep over one voxel, the partial-volume look of a scanned edge.
inline double inside(double d, double h) {
  double x = std::clamp(0.5 - d / h, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

// Approximate signed distance to an axis-aligned ellipsoid (exact on the surface and for
// spheres, first-order nearby, which is all the soft edges need).
inline double ellipsoid_distance(const glm::dvec3& p, const glm::dvec3& centre,
                                 const glm::dvec3& radii) {
  glm::dvec3 q = p - centre;
  double k1 = glm::length(q / (radii * radii));
  if (k1 < 1e-12) return -std::min({radii.x, radii.y, radii.z});
  double k0 = glm::length(q / radii);
  return k0 * (k0 - 1.0) / k1;
}

inline double sphere_distance(const glm::dvec3& p, const glm::dvec3& centre, double radius) {
  return glm::length(p - centre) - radius;
}

// Exact signed distance to an axis-aligned box of half-sizes `half` centred at the origin.
inline double box_distance(const glm::dvec3& p, const glm::dvec3& half) {
  glm::dvec3 q = glm::abs(p) - half;
  return glm::length(glm::max(q, 0.0)) + std::min(std::max({q.x, q.y, q.z}), 0.0);
}

// Stores `v` in a voxel of type T: rounded and clamped for integer types.
template <class T>
T to_voxel(double v) {
  if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(v);
  } else {
    double lo = std::numeric_limits<T>::lowest(), hi = std::numeric_limits<T>::max();
    return static_cast<T>(std::lround(std::clamp(v, lo, hi)));
  }
}

// A volume whose voxels are `field(world position)`, evaluated in parallel; every voxel
// depends only on its own position, so the bytes do not depend on the thread count.
template <class T, class Field>
VolumeData sample_field(glm::ivec3 dims, const glm::dmat4& index_to_world, const Field& field) {
  std::vector<T> voxels(static_cast<size_t>(dims.x) * dims.y * dims.z);
  parallel_for(static_cast<long>(dims.y) * dims.z, 0, [&](long begin, long end) {
    for (long row = begin; row < end; ++row) {
      int j = static_cast<int>(row % dims.y), k = static_cast<int>(row / dims.y);
      T* out = voxels.data() + static_cast<size_t>(row) * dims.x;
      for (int i = 0; i < dims.x; ++i)
        out[i] = to_voxel<T>(field(glm::dvec3(index_to_world * glm::dvec4(i, j, k, 1.0))));
    }
  });
  VolumeData v;
  v.dims = dims;
  v.voxels = std::move(voxels);
  v.index_to_world = index_to_world;
  return v;
}

}  // namespace imx::detail
