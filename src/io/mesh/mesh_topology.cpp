// check_closed and flipped: edge counting on welded positions, divergence-theorem volume.
#include "io/mesh/mesh_topology.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace imx {
namespace {

// Hashes a position by its bits; adding +0 first turns -0 into +0, which compare equal.
struct PositionKey {
  uint32_t x, y, z;
  bool operator==(const PositionKey&) const = default;
};

PositionKey key_of(const glm::vec3& p) {
  return {std::bit_cast<uint32_t>(p.x + 0.0f), std::bit_cast<uint32_t>(p.y + 0.0f),
          std::bit_cast<uint32_t>(p.z + 0.0f)};
}

struct PositionHash {
  size_t operator()(const PositionKey& k) const {
    uint64_t h = k.x;
    h = h * 0x9E3779B97F4A7C15ull ^ k.y;
    h = h * 0x9E3779B97F4A7C15ull ^ k.z;
    return static_cast<size_t>(h ^ (h >> 29));
  }
};

// Uses of one undirected edge {lo, hi}: as lo -> hi and as hi -> lo.
struct EdgeUses {
  uint32_t forward = 0, backward = 0;
};

}  // namespace

MeshTopology check_closed(const Mesh& mesh) {
  std::unordered_map<PositionKey, uint32_t, PositionHash> ids;
  ids.reserve(mesh.positions.size());
  std::vector<uint32_t> weld(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    weld[i] =
        ids.emplace(key_of(mesh.positions[i]), static_cast<uint32_t>(ids.size())).first->second;

  // Integrating about the bounding-box centre instead of the origin keeps the terms small for
  // meshes far from the origin; for a closed surface the result is the same.
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }
  const glm::dvec3 centre = mesh.positions.empty() ? glm::dvec3(0.0) : 0.5 * (lo + hi);

  MeshTopology out;
  std::unordered_map<uint64_t, EdgeUses> edges;
  edges.reserve(mesh.triangles.size() * 3 / 2 + 1);
  for (const glm::uvec3& t : mesh.triangles) {
    // A corner that names no vertex cannot be part of a closed surface: its edges count open.
    if (t.x >= weld.size() || t.y >= weld.size() || t.z >= weld.size()) {
      out.open_edges += 3;
      continue;
    }
    const uint32_t v[3] = {weld[t.x], weld[t.y], weld[t.z]};
    // A triangle with two welded corners alike is a line or a point: it bounds nothing and its
    // "edges" would only pair with themselves.
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
    for (int e = 0; e < 3; ++e) {
      const uint32_t from = v[e], to = v[(e + 1) % 3];
      const uint64_t key = (uint64_t{std::min(from, to)} << 32) | std::max(from, to);
      EdgeUses& uses = edges[key];
      (from < to ? uses.forward : uses.backward)++;
    }
    const glm::dvec3 a = glm::dvec3(mesh.positions[t.x]) - centre;
    const glm::dvec3 b = glm::dvec3(mesh.positions[t.y]) - centre;
    const glm::dvec3 c = glm::dvec3(mesh.positions[t.z]) - centre;
    out.signed_volume += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  for (const auto& [key, uses] : edges) {
    if (uses.forward + uses.backward != 2) ++out.open_edges;
    out.unpaired_edges +=
        uses.forward > uses.backward ? uses.forward - uses.backward : uses.backward - uses.forward;
  }
  return out;
}

Mesh flipped(const Mesh& mesh) {
  Mesh out = mesh;
  for (glm::uvec3& t : out.triangles) std::swap(t.y, t.z);
  for (glm::vec3& n : out.normals) n = -n;
  return out;
}

}  // namespace imx
