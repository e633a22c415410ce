// FSL's .bval/.bvec text files, as dcm2niix and intermix convert write them: for tests.
#pragma once
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

namespace imx::test {

// The numbers of each non-empty line.
inline std::vector<std::vector<double>> read_rows(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::istringstream s(line);
    std::vector<double> row;
    for (double v; s >> v;) row.push_back(v);
    if (!row.empty()) rows.push_back(row);
  }
  return rows;
}

// The world direction of a .bvec column `v` beside an image placed by `index_to_world`: along
// its voxel axes, x negated when the affine's determinant is positive (FSL's convention).
inline glm::dvec3 bvec_world(glm::dvec3 v, const glm::dmat4& index_to_world) {
  const glm::dmat3 m(index_to_world);
  if (glm::determinant(m) > 0.0) v.x = -v.x;
  const glm::dvec3 w =
      glm::normalize(m[0]) * v.x + glm::normalize(m[1]) * v.y + glm::normalize(m[2]) * v.z;
  return glm::length(w) > 1e-9 ? glm::normalize(w) : glm::dvec3(0.0);
}

}  // namespace imx::test
