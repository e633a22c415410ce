#include "server/slice_orientation.hpp"

#include <cmath>

#include <fmt/format.h>
#include <glm/glm.hpp>

namespace imx::server {

using scene_json::Range;

glm::dmat3 parse_rotation(const scene_json::JsonReader& r) {
  constexpr double kTolerance = 1e-3;
  r.expect_array();
  if (r.size() != 3) r.fail(fmt::format("expected 3 rows of 3 numbers, got {}", r.describe()));
  glm::dmat3 m(1.0);
  for (int i = 0; i < 3; ++i) {
    const std::vector<double> row =
        r.at(static_cast<size_t>(i)).numbers(3, Range::closed(-1.0 - kTolerance, 1.0 + kTolerance));
    for (int j = 0; j < 3; ++j) m[j][i] = row[static_cast<size_t>(j)];  // glm is column-major
  }
  const glm::dmat3 gram = glm::transpose(m) * m;
  double worst = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      worst = std::max(worst, std::abs(gram[i][j] - (i == j ? 1.0 : 0.0)));
  if (worst > kTolerance)
    r.fail(
        fmt::format("is not a rotation: its rows are not orthonormal (off by {:.3g}; "
                    "at most {} is rounding)",
                    worst, kTolerance));
  if (glm::determinant(m) < 0.0) r.fail("is not a rotation: its determinant is -1 (a mirror)");
  // Gram-Schmidt on the columns, so that the views' frames are exactly orthonormal.
  const glm::dvec3 x = glm::normalize(m[0]);
  const glm::dvec3 y = glm::normalize(m[1] - glm::dot(m[1], x) * x);
  return glm::dmat3(x, y, glm::cross(x, y));
}

}  // namespace imx::server
