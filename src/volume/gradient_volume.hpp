// GradientVolume: central-difference gradients precomputed at every voxel, sampled trilinearly.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "volume/any_grid.hpp"

namespace imx {

// Index-space gradients quantized to int16 per component with one scale for the whole volume
// (6 bytes a voxel instead of 12): shading needs the direction, and 1/32767 of the largest
// gradient is far below what Blinn-Phong can show. Depends only on the voxels, not on the TF.
class GradientVolume {
 public:
  GradientVolume() = default;
  // Central differences at voxel centres (one-sided at the borders), in parallel on up to
  // `threads` threads (0 = all).
  explicit GradientVolume(const AnyGrid& voxels, int threads = 0);

  // The gradient at index-space position p, trilinear between the voxel gradients (clamped).
  glm::vec3 sample(glm::vec3 p) const {
    glm::vec3 hi = glm::vec3(dims_ - 1);
    p = glm::clamp(p, glm::vec3(0.0f), hi);
    glm::ivec3 i0 = glm::min(glm::ivec3(p), glm::max(dims_ - 2, glm::ivec3(0)));
    glm::vec3 f = p - glm::vec3(i0);
    glm::ivec3 i1 = glm::min(i0 + 1, dims_ - 1);
    size_t sy = static_cast<size_t>(dims_.x), sz = sy * dims_.y;
    size_t base = i0.z * sz + i0.y * sy + i0.x;
    size_t dx = i1.x - i0.x, dy = (i1.y - i0.y) * sy, dz = (i1.z - i0.z) * sz;
    auto g = [&](size_t o) {
      const int16_t* v = &data_[3 * (base + o)];
      return glm::vec3(v[0], v[1], v[2]);
    };
    glm::vec3 c00 = glm::mix(g(0), g(dx), f.x), c10 = glm::mix(g(dy), g(dy + dx), f.x);
    glm::vec3 c01 = glm::mix(g(dz), g(dz + dx), f.x),
              c11 = glm::mix(g(dz + dy), g(dz + dy + dx), f.x);
    return scale_ * glm::mix(glm::mix(c00, c10, f.y), glm::mix(c01, c11, f.y), f.z);
  }

  size_t bytes() const { return data_.size() * sizeof(int16_t); }

 private:
  std::vector<int16_t> data_;  // x, y, z per voxel, voxels x-fastest
  glm::ivec3 dims_{1};
  float scale_ = 1.0f;  // int16 unit in value units per voxel
};

}  // namespace imx
