// Mesh: an indexed triangle mesh in world space (mm), with optional per-vertex normals.
#pragma once
#include <vector>

#include <glm/vec3.hpp>

namespace imx {

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty, or one per position
  std::vector<glm::uvec3> triangles;
};

}  // namespace imx
