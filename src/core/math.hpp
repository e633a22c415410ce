// Vector math for the renderer: GLM types and a few helpers used across modules.
#pragma once
#include <cmath>
#include <limits>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_inverse.hpp>

namespace imx {

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

inline bool all_finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

inline bool all_finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Transforms a point (w = 1) by an affine 4x4.
inline glm::dvec3 transform_point(const glm::dmat4& m, const glm::dvec3& p) {
  return glm::dvec3(m * glm::dvec4(p, 1.0));
}

// Transforms a direction (w = 0) by an affine 4x4.
inline glm::dvec3 transform_vector(const glm::dmat4& m, const glm::dvec3& v) {
  return glm::dvec3(m * glm::dvec4(v, 0.0));
}

}  // namespace imx
