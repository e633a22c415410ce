// VoxelGrid<T>: a typed, non-owning view of voxels with trilinear sampling in index space.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include <glm/glm.hpp>

#include "volume/sample_formulas.hpp"
#include "volume/sample_ops.hpp"

namespace imx {

// Whether a sample is "no data": NaN or infinite. NaN and inf voxels (a statistical map's outside
// of its mask) are no data, and a trilinear sample is non-finite exactly when a corner it reads
// is, so a sample with any non-finite corner is no data: transparent, never a maximum or an iso
// crossing, left out of integrals and gradients. Kernels test it only on volumes that have such
// voxels (PreparedVolume::no_data).
[[gnu::always_inline]] inline bool no_data(float s) {
  return !(std::abs(s) <= std::numeric_limits<float>::max());
}

template <class T>
struct VoxelGrid {
  using value_type = T;
  const T* data = nullptr;
  glm::ivec3 dims{0};

  float at(int i, int j, int k) const {
    return static_cast<float>(data[(static_cast<size_t>(k) * dims.y + j) * dims.x + i]);
  }

  // Trilinear interpolation at index-space position p (voxel centres at integers), clamped
  // to the grid, so p may lie anywhere in [0, dims - 1]. Forced inline: it is the innermost
  // operation of every ray marcher, and compilers otherwise keep it a call.
  [[gnu::always_inline]] float sample(glm::vec3 p) const {
    glm::vec3 hi = glm::vec3(dims - 1);
    p = {clamp_index(p.x, hi.x), clamp_index(p.y, hi.y), clamp_index(p.z, hi.z)};
    glm::ivec3 i0 = glm::min(glm::ivec3(p), glm::max(dims - 2, glm::ivec3(0)));
    glm::vec3 f = p - glm::vec3(i0);
    size_t sx = 1, sy = static_cast<size_t>(dims.x), sz = sy * dims.y;
    size_t base = i0.z * sz + i0.y * sy + i0.x * sx;
    // The far corner min(i0 + 1, dims - 1) is i0 + 1 on every axis of two or more voxels (i0 is
    // at most dims - 2 there) and i0 on an axis of one: per grid, not per sample, constant.
    size_t dx = dims.x > 1 ? sx : 0, dy = dims.y > 1 ? sy : 0, dz = dims.z > 1 ? sz : 0;
    const T* q = data + base;
    const float c[8] = {static_cast<float>(q[0]),       static_cast<float>(q[dx]),
                        static_cast<float>(q[dy]),      static_cast<float>(q[dy + dx]),
                        static_cast<float>(q[dz]),      static_cast<float>(q[dz + dx]),
                        static_cast<float>(q[dz + dy]), static_cast<float>(q[dz + dy + dx])};
    return sample_formulas::trilinear<ScalarOps>(c, f.x, f.y, f.z);
  }

  // Central-difference gradient in index space (one voxel each way) of the trilinear field.
  glm::vec3 gradient(glm::vec3 p) const {
    return 0.5f * glm::vec3(sample(p + glm::vec3(1, 0, 0)) - sample(p - glm::vec3(1, 0, 0)),
                            sample(p + glm::vec3(0, 1, 0)) - sample(p - glm::vec3(0, 1, 0)),
                            sample(p + glm::vec3(0, 0, 1)) - sample(p - glm::vec3(0, 0, 1)));
  }

  // gradient() as the marchers take it (sample_formulas::clamped_gradient): the 32 voxels around
  // p read once instead of six samples' 48; equal wherever p lies inside the grid, up to the
  // rounding of p +- 1. A grid of at least two voxels on every axis.
  [[gnu::always_inline]] glm::vec3 clamped_gradient(glm::vec3 p) const {
    const glm::vec3 hi = glm::vec3(dims - 1);
    p = {clamp_index(p.x, hi.x), clamp_index(p.y, hi.y), clamp_index(p.z, hi.z)};
    const glm::ivec3 last = dims - 2;
    const glm::ivec3 i0 = glm::min(glm::ivec3(p), last);
    const glm::vec3 f = p - glm::vec3(i0);
    const std::ptrdiff_t corner[3] = {i0.x, i0.y, i0.z};
    const std::ptrdiff_t sy = dims.x, sz = sy * dims.y;
    struct Rows {
      const T* data;
      void pair(std::ptrdiff_t at, bool, float& a, float& b) const {
        a = static_cast<float>(data[at]), b = static_cast<float>(data[at + 1]);
      }
    };
    const int last_corner[3] = {last.x, last.y, last.z};
    glm::vec3 g;
    sample_formulas::clamped_gradient<ScalarOps>(Rows{data}, i0.x + i0.y * sy + i0.z * sz, corner,
                                                 f.x, f.y, f.z, last_corner, sy, sz, g);
    return g;
  }

  // gradient() of a grid with no-data voxels: a difference whose sample on one side is no data is
  // taken one-sided against the centre sample, and is 0 when that is not possible either, so the
  // normal is finite wherever it is asked for.
  glm::vec3 gradient_of_data(glm::vec3 p) const {
    const float c = sample(p);
    const bool centre = !no_data(c);
    glm::vec3 g(0.0f);
    for (int a = 0; a < 3; ++a) {
      glm::vec3 e(0.0f);
      e[a] = 1.0f;
      const float up = sample(p + e), down = sample(p - e);
      const bool has_up = !no_data(up), has_down = !no_data(down);
      if (has_up && has_down)
        g[a] = 0.5f * (up - down);
      else if (has_up && centre)
        g[a] = up - c;
      else if (has_down && centre)
        g[a] = c - down;
    }
    return g;
  }

  // v clamped to [0, hi], NaN to 0: the index sample() computes from it is always in the grid.
  static float clamp_index(float v, float hi) { return v > 0.0f ? (v < hi ? v : hi) : 0.0f; }

  bool inside(glm::vec3 p) const {
    return p.x >= 0.0f && p.y >= 0.0f && p.z >= 0.0f && p.x <= dims.x - 1 && p.y <= dims.y - 1 &&
           p.z <= dims.z - 1;
  }
};

}  // namespace imx
