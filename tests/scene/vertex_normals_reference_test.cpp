// The parallel vertex normals against a one-core reference written from their definition
// (vertex_normals.hpp): the same vertices in the same order, the same normals bit for bit, the
// same triangles, at any thread count.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <numeric>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <glm/glm.hpp>

#include "io/mesh/vertex_normals.hpp"
#include "mesh_random.hpp"

namespace imx {
namespace {

struct Result {
  Mesh mesh;
  std::vector<uint32_t> origin;
};

std::array<uint32_t, 6> key_of(const Mesh& m, size_t i, bool by_color) {
  std::array<uint32_t, 6> key{};
  for (int c = 0; c < 3; ++c) {
    key[c] = std::bit_cast<uint32_t>(m.positions[i][c] + 0.0f);
    if (by_color) key[3 + c] = std::bit_cast<uint32_t>(m.colors[i][c] + 0.0f);
  }
  return key;
}

// Ids by first occurrence, and the first vertex of each id.
std::vector<uint32_t> weld(const Mesh& m, bool by_color, std::vector<uint32_t>& first) {
  std::map<std::array<uint32_t, 6>, uint32_t> ids;
  std::vector<uint32_t> out;
  for (size_t i = 0; i < m.positions.size(); ++i) {
    auto [it, fresh] = ids.emplace(key_of(m, i, by_color), static_cast<uint32_t>(first.size()));
    if (fresh) first.push_back(static_cast<uint32_t>(i));
    out.push_back(it->second);
  }
  return out;
}

uint32_t root(std::vector<uint32_t>& parent, uint32_t a) {
  while (parent[a] != a) a = parent[a];
  return a;
}

Result reference(const Mesh& in, double crease_deg) {
  const bool colored = !in.colors.empty();
  std::vector<uint32_t> first, place_first;
  const std::vector<uint32_t> w = weld(in, colored, first);
  const std::vector<uint32_t> place = weld(in, false, place_first);
  const size_t n = in.triangles.size();
  std::vector<glm::dvec3> face(n, glm::dvec3(0.0));
  std::vector<double> angle(3 * n, 0.0);
  for (size_t t = 0; t < n; ++t) {
    glm::dvec3 p[3];
    for (int k = 0; k < 3; ++k) p[k] = glm::dvec3(in.positions[in.triangles[t][k]]);
    const glm::dvec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
    const double len = glm::length(c);
    if (!(len > 0.0) || !std::isfinite(len)) continue;
    face[t] = c / len;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
      angle[3 * t + k] = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
    }
  }
  auto live = [&](uint32_t c) { return face[c / 3] != glm::dvec3(0.0); };
  auto place_of = [&](uint32_t c, int step) {
    return place[in.triangles[c / 3][(c % 3 + step) % 3]];
  };
  // At each place, the corners that share an other end, in corner order: neighbours join.
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> by_edge;
  for (uint32_t c = 0; c < 3 * n; ++c)
    if (live(c))
      for (int step : {1, 2}) by_edge[{place_of(c, 0), place_of(c, step)}].push_back(c);
  const double cos_crease = std::cos(crease_deg * std::numbers::pi / 180.0);
  std::vector<uint32_t> parent(3 * n);
  std::iota(parent.begin(), parent.end(), 0u);
  for (const auto& [edge, cs] : by_edge)
    for (size_t i = 1; i < cs.size(); ++i)
      if (glm::dot(face[cs[i] / 3], face[cs[i - 1] / 3]) >= cos_crease - 1e-12) {
        const uint32_t a = root(parent, cs[i]), b = root(parent, cs[i - 1]);
        parent[std::max(a, b)] = std::min(a, b);
      }
  std::vector<glm::dvec3> sum(3 * n, glm::dvec3(0.0));
  for (uint32_t c = 0; c < 3 * n; ++c) sum[root(parent, c)] += angle[c] * face[c / 3];

  Result r;
  r.mesh.triangles.resize(n);
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> vertex;
  std::vector<uint32_t> any(first.size(), UINT32_MAX);
  auto add = [&](uint32_t wv, const glm::dvec3& s) {
    r.mesh.positions.push_back(in.positions[first[wv]]);
    if (colored) r.mesh.colors.push_back(in.colors[first[wv]]);
    const double len = glm::length(s);
    r.mesh.normals.push_back(glm::vec3(len > 0.0 ? s / len : glm::dvec3(0.0)));
    r.origin.push_back(first[wv]);
    const uint32_t id = static_cast<uint32_t>(r.mesh.positions.size() - 1);
    if (any[wv] == UINT32_MAX) any[wv] = id;
    return id;
  };
  for (uint32_t c = 0; c < 3 * n; ++c) {
    if (!live(c)) continue;
    const uint32_t wv = w[in.triangles[c / 3][c % 3]], g = root(parent, c);
    auto it = vertex.find({wv, g});
    if (it == vertex.end()) it = vertex.emplace(std::pair{wv, g}, add(wv, sum[g])).first;
    r.mesh.triangles[c / 3][c % 3] = it->second;
  }
  for (uint32_t c = 0; c < 3 * n; ++c) {
    if (live(c)) continue;
    const uint32_t wv = w[in.triangles[c / 3][c % 3]];
    r.mesh.triangles[c / 3][c % 3] = any[wv] != UINT32_MAX ? any[wv] : add(wv, glm::dvec3(0.0));
  }
  return r;
}

bool same_bits(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  // memcmp of an empty vector's null data is undefined, even for 0 bytes.
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}

void expect_same(const Result& got, const Result& expected, const std::string& what) {
  EXPECT_EQ(got.origin, expected.origin) << what;
  EXPECT_TRUE(same_bits(got.mesh.positions, expected.mesh.positions)) << what;
  EXPECT_TRUE(same_bits(got.mesh.normals, expected.mesh.normals)) << what;
  EXPECT_TRUE(same_bits(got.mesh.colors, expected.mesh.colors)) << what;
  EXPECT_TRUE(got.mesh.triangles == expected.mesh.triangles) << what;
}

Result computed(Mesh m, double crease_deg) {
  Result r;
  detail::compute_vertex_normals(m, crease_deg, &r.origin);
  r.mesh = std::move(m);
  return r;
}

TEST(VertexNormalsReference, RandomMeshesMatchTheReferenceBitForBit) {
  for (bool colors : {false, true})
    for (double crease : {0.0, 30.0, 60.0, 120.0, 180.0}) {
      const Mesh m = test::random_mesh(colors ? 3 : 5, 3000, 9000, 20000, colors);
      const Result expected = reference(m, crease);
      const std::string what = fmt::format("colours {} crease {}", colors, crease);
      expect_same(computed(m, crease), expected, what);
      // The test sees what it should: splits, welds and degenerate triangles.
      EXPECT_GT(expected.mesh.positions.size(), 3000u) << what;
    }
}

TEST(VertexNormalsReference, OneThreadGivesTheSameBits) {
  const Mesh m = test::random_mesh(9, 20000, 60000, 150000, true);
  const Result all = computed(m, 45.0);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  expect_same(computed(m, 45.0), all, "one thread");
}

}  // namespace
}  // namespace imx
