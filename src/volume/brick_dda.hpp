// BrickDda: Amanatides-Woo walk over the bricks a ray crosses, with distance-map jumps (pure).
#pragma once
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "volume/brick_grid.hpp"

namespace imx {

// One brick on the ray and the part [t_enter, t_exit) of the ray inside its cell.
struct BrickSpan {
  glm::ivec3 brick{0};
  float t_enter = 0.0f;
  float t_exit = 0.0f;
};

// Walks the bricks of a BrickGrid in ray order over [t0, t1]. The ray is given in index space
// (voxel centres at integers); t is whatever parameter the caller uses (world mm for
// PreparedVolume rays, since the index map is affine), and dir need not be normalized. The walk
// ends only at t1: a ray that rounding puts just outside the grid stays in the border brick,
// where the sampler clamps too. Every crossing time is computed from the brick index alone,
// never accumulated, so skip() lands exactly where a run of next() would have. Pure: no
// allocation, no exceptions.
class BrickDda {
 public:
  BrickDda() = default;
  BrickDda(const BrickGrid& grid, glm::vec3 origin, glm::vec3 dir, float t0, float t1)
      : dims_(grid.dims), size_(grid.size), origin_(origin), t_enter_(t0), t1_(t1) {
    done_ = !(t1 > t0);
    glm::vec3 p = origin + t0 * dir;
    for (int a = 0; a < 3; ++a) {
      // Rays this close to parallel never cross a boundary inside any grid (as in intersect()).
      if (std::abs(dir[a]) < 1e-12f) {
        step_[a] = 0;
        inv_dir_[a] = 0.0f;
      } else {
        step_[a] = dir[a] > 0.0f ? 1 : -1;
        inv_dir_[a] = 1.0f / dir[a];
      }
      // A start exactly on a boundary belongs to the cell the ray moves into.
      float x = p[a] / size_[a];
      float c = step_[a] < 0 ? std::ceil(x) - 1.0f : std::floor(x);
      c = c > 0.0f ? std::min(c, static_cast<float>(dims_[a] - 1)) : 0.0f;  // NaN goes to 0
      cell_[a] = static_cast<int>(c);
      t_max_[a] = crossing(a, cell_[a]);
    }
  }

  bool done() const { return done_; }
  glm::ivec3 brick() const { return cell_; }
  float t_enter() const { return t_enter_; }
  float t_exit() const {
    float t = std::min(std::min(t_max_.x, t_max_.y), std::min(t_max_.z, t1_));
    return std::max(t, t_enter_);
  }
  BrickSpan span() const { return {cell_, t_enter_, t_exit()}; }

  // Moves to the next brick along the ray (ties between axes go to the lowest axis).
  void next() {
    int a = first_axis(t_max_);
    if (!(t_max_[a] < t1_)) {
      done_ = true;
      return;
    }
    t_enter_ = std::max(t_enter_, t_max_[a]);
    cell_[a] += step_[a];
    t_max_[a] = crossing(a, cell_[a]);
  }

  // The octant the ray moves into (octant_distance()): bit a set where it steps down axis a.
  int octant() const {
    return (step_.x < 0 ? 1 : 0) | (step_.y < 0 ? 2 : 0) | (step_.z < 0 ? 4 : 0);
  }

  // Skips the bricks up to d-1 ahead of the current one on every axis, which the caller knows
  // are all empty (its distance-map value toward octant() is d): the ray leaves that cube of
  // bricks where it first crosses one of the cube's far faces, and continues in the brick just
  // beyond, exactly as a run of next() would have. skip(1) == next().
  void skip(int d) {
    if (d <= 1) {
      next();
      return;
    }
    // The cube's far face per axis; where the cube reaches the grid's edge there is none.
    glm::ivec3 last;
    glm::vec3 exit_t;
    for (int a = 0; a < 3; ++a) {
      last[a] = std::clamp(cell_[a] + (d - 1) * step_[a], 0, dims_[a] - 1);
      exit_t[a] = crossing(a, last[a]);
    }
    int ax = first_axis(exit_t);
    float t = exit_t[ax];
    if (!(t < t1_)) {
      done_ = true;
      return;
    }
    for (int b = 0; b < 3; ++b) {
      if (b == ax) continue;
      // Crossings next() would make on axis b before the exit event (t, ax): a monotone
      // predicate of m, false at the cube's last cell (ax exits first, or b never crosses).
      int lo = 0, hi = std::abs(last[b] - cell_[b]);
      while (lo < hi) {
        int mid = (lo + hi) / 2;
        float tm = crossing(b, cell_[b] + mid * step_[b]);
        if (tm < t || (tm == t && b < ax))
          lo = mid + 1;
        else
          hi = mid;
      }
      cell_[b] += lo * step_[b];
    }
    cell_[ax] = last[ax] + step_[ax];
    t_enter_ = std::max(t_enter_, t);
    for (int a = 0; a < 3; ++a) t_max_[a] = crossing(a, cell_[a]);
  }

 private:
  // When the ray leaves brick j of axis a for the next brick (infinity if it never does, or if
  // that brick is outside the grid: positions there clamp to the border brick, as samples do).
  float crossing(int a, int j) const {
    int next = j + step_[a];
    if (step_[a] == 0 || next < 0 || next >= dims_[a]) return INFINITY;
    float plane = static_cast<float>(step_[a] > 0 ? next : j) * size_[a];
    return (plane - origin_[a]) * inv_dir_[a];
  }
  static int first_axis(const glm::vec3& t) {
    if (t.x <= t.y) return t.x <= t.z ? 0 : 2;
    return t.y <= t.z ? 1 : 2;
  }

  glm::ivec3 dims_{1};
  glm::vec3 size_{1.0f};  // cells per brick along each axis
  glm::vec3 origin_{0.0f};
  glm::vec3 inv_dir_{0.0f};
  glm::ivec3 step_{0};
  glm::ivec3 cell_{0};
  glm::vec3 t_max_{INFINITY};
  float t_enter_ = 0.0f;
  float t1_ = 0.0f;
  bool done_ = true;
};

}  // namespace imx
