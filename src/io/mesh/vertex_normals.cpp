#include "io/mesh/vertex_normals.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "intermix/limits.hpp"

namespace imx::detail {
namespace {

// A vertex by the bits of its position and colour (+0 first: -0 and +0 weld).
struct VertexKey {
  uint32_t bits[6];
  bool operator==(const VertexKey&) const = default;
};

struct VertexKeyHash {
  size_t operator()(const VertexKey& k) const {
    uint64_t h = 0;
    for (uint32_t b : k.bits) h = (h ^ b) * 0x9E3779B97F4A7C15ull;
    return static_cast<size_t>(h ^ (h >> 29));
  }
};

uint32_t bits(float f) {
  return std::bit_cast<uint32_t>(f + 0.0f);
}

// Union-find over face corners, with path halving.
struct Groups {
  std::vector<uint32_t> parent;
  explicit Groups(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void join(uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// Welds vertices of equal position and colour; returns the welded vertex of each input one.
std::vector<uint32_t> weld(const Mesh& mesh, std::vector<uint32_t>& first_of) {
  const bool colored = mesh.colors.size() == mesh.positions.size();
  std::unordered_map<VertexKey, uint32_t, VertexKeyHash> ids;
  ids.reserve(mesh.positions.size());
  std::vector<uint32_t> out(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3& p = mesh.positions[i];
    const glm::vec3 c = colored ? mesh.colors[i] : glm::vec3(0.0f);
    VertexKey key{{bits(p.x), bits(p.y), bits(p.z), bits(c.x), bits(c.y), bits(c.z)}};
    auto [it, fresh] = ids.emplace(key, static_cast<uint32_t>(first_of.size()));
    if (fresh) first_of.push_back(static_cast<uint32_t>(i));
    out[i] = it->second;
  }
  return out;
}

}  // namespace

void compute_vertex_normals(Mesh& mesh, double crease_deg, std::vector<uint32_t>* origin) {
  const size_t n_tri = mesh.triangles.size();
  check_memory(uint64_t{n_tri} * 3 * 64 + uint64_t{mesh.positions.size()} * 48,
               "computing the vertex normals of a mesh");
  std::vector<uint32_t> source;  // welded vertex -> an input vertex holding its data
  const std::vector<uint32_t> welded = weld(mesh, source);
  // Adjacency goes by position alone: a colour seam is no crease.
  std::vector<uint32_t> place_of_source;
  std::vector<uint32_t> place;
  {
    Mesh positions_only;
    positions_only.positions = mesh.positions;
    place = weld(positions_only, place_of_source);
  }

  // Unit face normals and corner angles, in double precision.
  std::vector<glm::dvec3> face(n_tri);
  std::vector<double> angle(3 * n_tri, 0.0);
  for (size_t t = 0; t < n_tri; ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    const glm::dvec3 p[3] = {glm::dvec3(mesh.positions[tri.x]), glm::dvec3(mesh.positions[tri.y]),
                             glm::dvec3(mesh.positions[tri.z])};
    const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
    const double len = glm::length(n);
    if (!(len > 0.0) || !std::isfinite(len)) continue;  // degenerate: zero normal, no weight
    face[t] = n / len;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
      angle[3 * t + k] = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
    }
  }

  // Corners around each place (welded position), as compressed rows.
  const size_t n_places = place_of_source.size();
  std::vector<uint32_t> offsets(n_places + 1, 0);
  for (const glm::uvec3& tri : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++offsets[place[tri[k]] + 1];
  std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
  std::vector<uint32_t> corners(3 * n_tri);
  {
    std::vector<uint32_t> fill(offsets.begin(), offsets.end() - 1);
    for (size_t t = 0; t < n_tri; ++t)
      for (int k = 0; k < 3; ++k)
        corners[fill[place[mesh.triangles[t][k]]]++] = static_cast<uint32_t>(3 * t + k);
  }

  // Two corners at one place join when their faces share an edge there (the same other end)
  // and meet at no more than the crease angle; sorting by the other end finds the pairs in
  // O(k log k) for k corners, however many faces a hostile fan puts around one vertex.
  const double cos_crease = std::cos(std::clamp(crease_deg, 0.0, 180.0) * std::numbers::pi / 180.0);
  Groups groups(3 * n_tri);
  std::vector<std::pair<uint32_t, uint32_t>> ends;  // (other end's place, corner)
  for (size_t v = 0; v < n_places; ++v) {
    ends.clear();
    for (uint32_t i = offsets[v]; i < offsets[v + 1]; ++i) {
      const uint32_t c = corners[i], t = c / 3, k = c % 3;
      if (face[t] == glm::dvec3(0.0)) continue;
      ends.emplace_back(place[mesh.triangles[t][(k + 1) % 3]], c);
      ends.emplace_back(place[mesh.triangles[t][(k + 2) % 3]], c);
    }
    std::sort(ends.begin(), ends.end());
    for (size_t i = 1; i < ends.size(); ++i)
      if (ends[i].first == ends[i - 1].first &&
          glm::dot(face[ends[i].second / 3], face[ends[i - 1].second / 3]) >= cos_crease - 1e-12)
        groups.join(ends[i].second, ends[i - 1].second);
  }

  // Each group's angle-weighted normal, summed in corner order (deterministic).
  std::vector<glm::dvec3> sum(3 * n_tri, glm::dvec3(0.0));
  for (uint32_t c = 0; c < 3 * n_tri; ++c) sum[groups.find(c)] += angle[c] * face[c / 3];

  // One output vertex per (welded vertex, group). Degenerate triangles come last and reuse a
  // vertex of their corner where there is one: they show nothing and need no normal.
  const bool colored = mesh.colors.size() == mesh.positions.size();
  Mesh out;
  std::unordered_map<uint64_t, uint32_t> vertex_of;
  vertex_of.reserve(mesh.positions.size());
  std::vector<uint32_t> any_vertex(source.size(), UINT32_MAX);
  if (origin) origin->clear();
  out.triangles.resize(n_tri);
  for (int degenerate = 0; degenerate < 2; ++degenerate)
    for (uint32_t c = 0; c < 3 * n_tri; ++c) {
      const uint32_t t = c / 3, k = c % 3, root = groups.find(c);
      if ((face[t] == glm::dvec3(0.0)) != (degenerate == 1)) continue;
      const uint32_t w = welded[mesh.triangles[t][k]];
      if (degenerate && any_vertex[w] != UINT32_MAX) {
        out.triangles[t][k] = any_vertex[w];
        continue;
      }
      const uint64_t key = (uint64_t{w} << 32) | root;
      auto [it, fresh] = vertex_of.emplace(key, static_cast<uint32_t>(out.positions.size()));
      if (fresh) {
        out.positions.push_back(mesh.positions[source[w]]);
        if (origin) origin->push_back(source[w]);
        if (colored) out.colors.push_back(mesh.colors[source[w]]);
        const double len = glm::length(sum[root]);
        out.normals.emplace_back(len > 0.0 && std::isfinite(len) ? sum[root] / len
                                                                 : glm::dvec3(0.0));
        if (any_vertex[w] == UINT32_MAX) any_vertex[w] = it->second;
      }
      out.triangles[t][k] = it->second;
    }
  mesh = std::move(out);
}

}  // namespace imx::detail
