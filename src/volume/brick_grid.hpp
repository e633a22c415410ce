// BrickGrid: how a voxel grid is cut into bricks of Bx x By x Bz cells, and which voxels each
// brick reads.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>

#include <glm/glm.hpp>

namespace imx {

// Brick b (per axis a) owns the closed index-space region [b*B_a, (b+1)*B_a] clipped to the hull
// [0, N-1]. Neighbouring regions share their boundary face, so every sample position lies in
// at least one brick. A trilinear sample at p reads voxels floor(p) and ceil(p) with non-zero
// weight, so over the region it depends exactly on voxels [b*B, min((b+1)*B, N-1)]: B+1 voxels,
// the brick's own B plus a one-voxel apron at the high end (see docs/volume_acceleration.md).
struct BrickGrid {
  static constexpr int kDefaultSize = 8;

  glm::ivec3 voxel_dims{1};
  glm::ivec3 size{kDefaultSize};  // B per axis, in voxels (index units)
  glm::ivec3 dims{1};             // bricks per axis

  BrickGrid() = default;
  BrickGrid(glm::ivec3 voxels, glm::ivec3 shape) : voxel_dims(voxels), size(shape) {
    // ceil((N-1)/B) bricks cover [0, N-1]; a one-voxel axis still gets one (degenerate) brick.
    for (int a = 0; a < 3; ++a) dims[a] = std::max(1, (voxel_dims[a] - 1 + size[a] - 1) / size[a]);
  }
  BrickGrid(glm::ivec3 voxels, int cube) : BrickGrid(voxels, glm::ivec3(cube)) {}

  // The brick shape for `voxels` voxels `spacing` mm apart along i, j, k: `cells` cells along the
  // finest axis and about as many mm along the others (at least one cell), so that a brick is
  // close to a cube in the world. A CT of 0.45 x 0.45 x 5 mm voxels gets 8 x 8 x 1 cells, not a
  // 3.6 x 3.6 x 40 mm column whose one bone voxel makes every ray through it march. Spacings
  // that are not positive and finite give a cube. Grids of more than kMaxBricks bricks take
  // twice the cells on every axis until they fit: the tables stay below 64 MiB, and the packet
  // walk's float brick indices exact.
  static constexpr size_t kMaxBricks = size_t{1} << 22;
  static glm::ivec3 shape_for(int cells, glm::dvec3 spacing, glm::ivec3 voxels) {
    glm::ivec3 shape(cells);
    bool known = true;
    for (int a = 0; a < 3; ++a) known = known && spacing[a] > 0.0 && std::isfinite(spacing[a]);
    if (known) {
      const double finest = std::min({spacing.x, spacing.y, spacing.z});
      for (int a = 0; a < 3; ++a)
        shape[a] = std::clamp(static_cast<int>(std::lround(cells * finest / spacing[a])), 1, cells);
    }
    while (BrickGrid(voxels, shape).count() > kMaxBricks && glm::any(glm::lessThan(shape, voxels)))
      shape *= 2;
    return shape;
  }

  size_t count() const { return static_cast<size_t>(dims.x) * dims.y * dims.z; }
  size_t index(glm::ivec3 b) const {
    return (static_cast<size_t>(b.z) * dims.y + b.y) * dims.x + b.x;
  }

  // First and last voxel (inclusive) that trilinear samples inside brick b can read.
  glm::ivec3 first_voxel(glm::ivec3 b) const { return b * size; }
  glm::ivec3 last_voxel(glm::ivec3 b) const { return glm::min((b + 1) * size, voxel_dims - 1); }

  // The brick whose half-open cell [b*B, (b+1)*B) holds index-space position p, clamped to the
  // grid (the last brick also takes p = N-1 and anything beyond).
  glm::ivec3 brick_of(glm::vec3 p) const {
    glm::ivec3 b;
    for (int a = 0; a < 3; ++a) {
      float f = std::floor(p[a] / static_cast<float>(size[a]));
      f = f > 0.0f ? std::min(f, static_cast<float>(dims[a] - 1)) : 0.0f;  // NaN goes to 0
      b[a] = static_cast<int>(f);
    }
    return b;
  }
};

}  // namespace imx
