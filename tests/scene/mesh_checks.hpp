// Mesh topology checks for the scene tests, written apart from io/mesh/mesh_topology.hpp's so that
// they check it too: closed and consistently wound, and the enclosed volume.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "intermix/mesh.hpp"

namespace imx::test {

// True when, after welding equal positions, every undirected edge is used by exactly two
// triangles in opposite directions (a closed, consistently wound 2-manifold).
inline bool is_closed_and_oriented(const Mesh& mesh, std::string* why = nullptr) {
  std::map<std::tuple<float, float, float>, uint32_t> ids;
  std::vector<uint32_t> weld(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3& p = mesh.positions[i];
    weld[i] = ids.emplace(std::make_tuple(p.x, p.y, p.z), static_cast<uint32_t>(ids.size()))
                  .first->second;
  }
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const glm::uvec3& t : mesh.triangles) {
    uint32_t v[3] = {weld[t.x], weld[t.y], weld[t.z]};
    for (int e = 0; e < 3; ++e) directed[{v[e], v[(e + 1) % 3]}]++;
  }
  for (const auto& [edge, count] : directed) {
    auto back = directed.find({edge.second, edge.first});
    if (count != 1 || back == directed.end() || back->second != 1) {
      if (why)
        *why = "edge " + std::to_string(edge.first) + "-" + std::to_string(edge.second) + " used " +
               std::to_string(count) + " times, reverse " +
               std::to_string(back == directed.end() ? 0 : back->second);
      return false;
    }
  }
  return true;
}

// Enclosed volume by the divergence theorem: positive when the triangles face outward.
inline double signed_volume(const Mesh& mesh) {
  double sum = 0.0;
  for (const glm::uvec3& t : mesh.triangles) {
    glm::dvec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
    sum += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  return sum;
}

}  // namespace imx::test
