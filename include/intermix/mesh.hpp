// Mesh: an indexed triangle mesh in world space (mm), with optional per-vertex normals and colours.
#pragma once
#include <vector>

#include <glm/vec3.hpp>

namespace imx {

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty, or one per position (shading only, never geometry)
  std::vector<glm::vec3> colors;   // empty, or one linear RGB per position; scales the material
  std::vector<glm::uvec3> triangles;
};

}  // namespace imx
