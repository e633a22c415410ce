// Volumes for the writer/reader round trips: every voxel different, on an oblique affine with
// unequal spacings and a non-integer origin, so that a swapped axis or a lost digit shows.
#pragma once
#include <cmath>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "intermix/volume.hpp"

namespace imx::test {

inline glm::dmat4 oblique_affine() {
  glm::dmat4 m = glm::rotate(glm::dmat4(1.0), 0.4, glm::normalize(glm::dvec3(1.0, -2.0, 0.5)));
  m = m * glm::scale(glm::dmat4(1.0), glm::dvec3(0.7, 1.3, 2.25));
  m[3] = glm::dvec4(-12.5, 33.0 / 7.0, 101.125, 1.0);
  return m;
}

template <class T>
VolumeData pattern_volume(glm::ivec3 dims) {
  std::vector<T> v(static_cast<size_t>(dims.x) * dims.y * dims.z);
  for (size_t i = 0; i < v.size(); ++i) {
    if constexpr (std::is_floating_point_v<T>)
      v[i] = static_cast<T>(std::sin(0.37 * static_cast<double>(i)) * 1e3);
    else
      v[i] = static_cast<T>(i * 7919u + (std::is_signed_v<T> ? -20000 : 0));
  }
  VolumeData out;
  out.dims = dims;
  out.voxels = std::move(v);
  out.index_to_world = oblique_affine();
  return out;
}

// Every entry of `a` within `tol` of `b`'s.
inline void expect_same_affine(const glm::dmat4& a, const glm::dmat4& b, double tol) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      EXPECT_NEAR(a[c][r], b[c][r], tol) << "entry [" << c << "][" << r << "]";
}

}  // namespace imx::test
