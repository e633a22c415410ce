// Random meshes for the parallel mesh code's tests: duplicate vertices (some as -0), colours,
// creases of every angle, non-manifold edges and degenerate triangles.
#pragma once
#include <cstdint>
#include <random>

#include <glm/glm.hpp>

#include "intermix/mesh.hpp"

namespace imx::test {

// `vertices` vertices, each a copy of one of `points` random points (so many weld), and
// `triangles` triangles over nearby vertices; one in 50 repeats a corner (degenerate).
inline Mesh random_mesh(uint32_t seed, size_t points, size_t vertices, size_t triangles,
                        bool colors) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<glm::vec3> pool(points), tint(points);
  for (size_t i = 0; i < points; ++i) {
    pool[i] = {unit(rng), unit(rng), unit(rng) * 0.2f};
    if (i % 7 == 0) pool[i].x = 0.0f;
    tint[i] = {0.5f + 0.5f * unit(rng), 0.5f, 0.5f};
  }
  Mesh m;
  std::uniform_int_distribution<size_t> pick(0, points - 1);
  for (size_t v = 0; v < vertices; ++v) {
    const size_t p = v < points ? v : pick(rng);
    glm::vec3 q = pool[p];
    if (q.x == 0.0f && v % 2 == 1) q.x = -0.0f;  // welds with +0
    m.positions.push_back(q);
    // Two colours per point: a colour seam welds apart, yet is no crease.
    if (colors) m.colors.push_back(v % 5 == 0 ? tint[p] * 0.5f : tint[p]);
  }
  std::uniform_int_distribution<int> near(-40, 40);
  for (size_t t = 0; t < triangles; ++t) {
    const int64_t a = static_cast<int64_t>(pick(rng) % vertices);
    auto other = [&] {
      return static_cast<uint32_t>((a + near(rng) + static_cast<int64_t>(vertices)) %
                                   static_cast<int64_t>(vertices));
    };
    glm::uvec3 tri{static_cast<uint32_t>(a), other(), other()};
    if (t % 50 == 0) tri.z = tri.y;
    m.triangles.push_back(tri);
  }
  return m;
}

}  // namespace imx::test
