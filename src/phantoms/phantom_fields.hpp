// Building blocks of the built-in phantoms: centred grids, signed distances, soft edges.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "core/parallel.hpp"
#include "intermix/volume.hpp"
#include "phantoms/phantoms.hpp"

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

// The voxels of `box` of a grid placed by `index_to_world`, each `field(world position)`,
// evaluated in parallel. Every voxel depends only on its own index in the whole grid (not the
// box's), so the bytes depend neither on the thread count nor on the box: a box's voxels are
// exactly the whole's voxels there.
template <class T, class Field>
VolumeData sample_field(const glm::dmat4& index_to_world, const VoxelBox& box, const Field& field) {
  const glm::ivec3 size = box.size();
  std::vector<T> voxels(box.count());
  parallel_for(static_cast<long>(size.y) * size.z, 0, [&](long begin, long end) {
    for (long row = begin; row < end; ++row) {
      int j = box.lo.y + static_cast<int>(row % size.y);
      int k = box.lo.z + static_cast<int>(row / size.y);
      T* out = voxels.data() + static_cast<size_t>(row) * size.x;
      for (int i = box.lo.x; i < box.hi.x; ++i)
        out[i - box.lo.x] =
            to_voxel<T>(field(glm::dvec3(index_to_world * glm::dvec4(i, j, k, 1.0))));
    }
  });
  VolumeData v;
  v.dims = size;
  v.voxels = std::move(voxels);
  v.index_to_world = box_index_to_world(index_to_world, box.lo);
  return v;
}

// The voxel type that stores T.
template <class T>
constexpr VoxelType voxel_type_of() {
  if constexpr (std::is_same_v<T, uint8_t>)
    return VoxelType::u8;
  else if constexpr (std::is_same_v<T, int16_t>)
    return VoxelType::i16;
  else if constexpr (std::is_same_v<T, uint16_t>)
    return VoxelType::u16;
  else
    return VoxelType::f32;
}

// A phantom of T voxels on a grid of `dims` placed by `index_to_world`, whose voxels are
// `field(world position)`; `field` is kept (by value) to sample any box later.
template <class T, class Field>
Phantom field_phantom(glm::ivec3 dims, const glm::dmat4& index_to_world, Field field) {
  Phantom p;
  p.header = {dims, voxel_type_of<T>(), index_to_world, 1, {}};
  p.sample = [index_to_world, field = std::move(field)](const VoxelBox& box) {
    return sample_field<T>(index_to_world, box, field);
  };
  return p;
}

}  // namespace imx::detail
