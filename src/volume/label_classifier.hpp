// Label volumes (style "labels"): a colour table made ready for a frame (LabelLooks), and the
// per-sample classification every method uses. Pure: no allocation, no exceptions.
//
// A sample is classified by the labels' interpolated indicator functions: of the eight voxels
// around it, each label's trilinear weights are summed and the label with the largest sum wins
// (ties: the smaller value). The winner is always a label of those eight voxels, so between
// labels a and b only a or b shows, never a third label that a trilinearly interpolated value
// would pass through; the boundary is the half-level set of the indicators, smooth within a
// voxel. Hidden labels and background compete like the others, so hiding one label moves no
// other label's boundary: a sample it wins is empty.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "intermix/labels.hpp"
#include "volume/voxel_grid.hpp"

namespace imx {

// What a label volume shows of each label, per frame: straight RGB and the opacity of
// unit_distance() mm (0: hidden).
class LabelLooks {
 public:
  LabelLooks() = default;
  explicit LabelLooks(const LabelMap& map);

  bool active() const { return active_; }
  bool nearest() const { return nearest_; }
  float unit_distance() const { return unit_distance_; }
  // 0 when the volume is not shown (LabelMap::shown): then it is not marched at all.
  float max_opacity() const { return shown_ ? max_opacity_ : 0.0f; }
  bool shown() const { return shown_; }

  glm::vec4 look(int32_t label) const {
    const int64_t i = static_cast<int64_t>(label) - lo_;
    if (i >= 0 && i < static_cast<int64_t>(dense_.size())) return dense_[static_cast<size_t>(i)];
    return look_outside(label);
  }

  // Whether some label in [lo, hi] (value range of voxels) shows: a brick whose voxels span
  // [lo, hi] can show nothing otherwise, as a sample's winner is one of its voxels' labels.
  bool any_shown_in(float lo, float hi) const;

 private:
  glm::vec4 look_outside(int32_t label) const;

  bool active_ = false, nearest_ = false, palette_ = false, shown_ = true;
  float unit_distance_ = 1.0f, max_opacity_ = 0.0f;
  int64_t lo_ = 0;
  std::vector<glm::vec4> dense_;                        // looks of lo_ .. lo_ + size - 1
  std::vector<std::pair<int32_t, glm::vec4>> listed_;   // every listed label, sorted
  std::vector<int32_t> shown_listed_, unshown_listed_;  // sorted values (0 counts as listed)
};

// The label value of a voxel (float label volumes hold integers, checked at load).
template <class T>
[[gnu::always_inline]] inline int32_t label_of(T v) {
  return static_cast<int32_t>(v);
}

// The winning label at index-space position p (clamped to the grid like VoxelGrid::sample).
template <class T>
[[gnu::always_inline]] inline int32_t winning_label(const VoxelGrid<T>& g, glm::vec3 p,
                                                    bool nearest) {
  const glm::vec3 hi = glm::vec3(g.dims - 1);
  p = {VoxelGrid<T>::clamp_index(p.x, hi.x), VoxelGrid<T>::clamp_index(p.y, hi.y),
       VoxelGrid<T>::clamp_index(p.z, hi.z)};
  const size_t sy = static_cast<size_t>(g.dims.x), sz = sy * static_cast<size_t>(g.dims.y);
  if (nearest) {
    const glm::ivec3 n = glm::min(glm::ivec3(p + 0.5f), g.dims - 1);
    return label_of(g.data[n.z * sz + n.y * sy + n.x]);
  }
  const glm::ivec3 i0 = glm::min(glm::ivec3(p), glm::max(g.dims - 2, glm::ivec3(0)));
  const glm::vec3 f = p - glm::vec3(i0);
  const size_t dx = g.dims.x > 1 ? 1 : 0, dy = g.dims.y > 1 ? sy : 0, dz = g.dims.z > 1 ? sz : 0;
  const T* q = g.data + (i0.z * sz + i0.y * sy + i0.x);
  const int32_t c[8] = {label_of(q[0]),       label_of(q[dx]),          label_of(q[dy]),
                        label_of(q[dy + dx]), label_of(q[dz]),          label_of(q[dz + dx]),
                        label_of(q[dz + dy]), label_of(q[dz + dy + dx])};
  if (c[0] == c[1] && c[0] == c[2] && c[0] == c[3] && c[0] == c[4] && c[0] == c[5] &&
      c[0] == c[6] && c[0] == c[7])
    return c[0];  // inside one label: most samples
  const float gx = 1.0f - f.x, gy = 1.0f - f.y, gz = 1.0f - f.z;
  const float w[8] = {gx * gy * gz,  f.x * gy * gz,  gx * f.y * gz,  f.x * f.y * gz,
                      gx * gy * f.z, f.x * gy * f.z, gx * f.y * f.z, f.x * f.y * f.z};
  int32_t best = c[0];
  float best_w = -1.0f;
  for (int i = 0; i < 8; ++i) {
    bool counted = false;
    for (int j = 0; j < i; ++j) counted |= c[j] == c[i];
    if (counted) continue;
    float sum = w[i];
    for (int j = i + 1; j < 8; ++j) sum += c[j] == c[i] ? w[j] : 0.0f;
    if (sum > best_w || (sum == best_w && c[i] < best)) best = c[i], best_w = sum;
  }
  return best;
}

// The trilinear interpolation of label `label`'s indicator (1 where a voxel holds it) at p.
template <class T>
inline float label_indicator(const VoxelGrid<T>& g, glm::vec3 p, int32_t label) {
  const glm::vec3 hi = glm::vec3(g.dims - 1);
  p = {VoxelGrid<T>::clamp_index(p.x, hi.x), VoxelGrid<T>::clamp_index(p.y, hi.y),
       VoxelGrid<T>::clamp_index(p.z, hi.z)};
  const glm::ivec3 i0 = glm::min(glm::ivec3(p), glm::max(g.dims - 2, glm::ivec3(0)));
  const glm::vec3 f = p - glm::vec3(i0);
  const size_t sy = static_cast<size_t>(g.dims.x), sz = sy * static_cast<size_t>(g.dims.y);
  const size_t dx = g.dims.x > 1 ? 1 : 0, dy = g.dims.y > 1 ? sy : 0, dz = g.dims.z > 1 ? sz : 0;
  const T* q = g.data + (i0.z * sz + i0.y * sy + i0.x);
  auto is = [&](size_t o) { return label_of(q[o]) == label ? 1.0f : 0.0f; };
  const float c00 = is(0) + f.x * (is(dx) - is(0)), c10 = is(dy) + f.x * (is(dy + dx) - is(dy));
  const float c01 = is(dz) + f.x * (is(dz + dx) - is(dz));
  const float c11 = is(dz + dy) + f.x * (is(dz + dy + dx) - is(dz + dy));
  const float c0 = c00 + f.y * (c10 - c00), c1 = c01 + f.y * (c11 - c01);
  return c0 + f.z * (c1 - c0);
}

// Index-space gradient of the label's indicator (central differences, one voxel each way): the
// shading normal of the winning label, pointing into it.
template <class T>
inline glm::vec3 label_gradient(const VoxelGrid<T>& g, glm::vec3 p, int32_t label) {
  return 0.5f * glm::vec3(label_indicator(g, p + glm::vec3(1, 0, 0), label) -
                              label_indicator(g, p - glm::vec3(1, 0, 0), label),
                          label_indicator(g, p + glm::vec3(0, 1, 0), label) -
                              label_indicator(g, p - glm::vec3(0, 1, 0), label),
                          label_indicator(g, p + glm::vec3(0, 0, 1), label) -
                              label_indicator(g, p - glm::vec3(0, 0, 1), label));
}

}  // namespace imx
