#include "tubes/tube_selection.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>
#include <glm/glm.hpp>

namespace imx {
namespace {

// Ray parity along +x: the number of triangles the ray from `p` crosses is odd inside a
// closed mesh.
bool inside_mesh(const Mesh& mesh, const glm::vec3& p) {
  int crossings = 0;
  for (const glm::uvec3& tri : mesh.triangles) {
    const glm::dvec3 a(mesh.positions[tri[0]]), b(mesh.positions[tri[1]]),
        c(mesh.positions[tri[2]]);
    // Project onto the y-z plane: is (p.y, p.z) inside the triangle, and is the crossing at x >
    // p.x?
    const glm::dvec2 q(p.y, p.z), pa(a.y, a.z), pb(b.y, b.z), pc(c.y, c.z);
    auto edge = [](const glm::dvec2& u, const glm::dvec2& v, const glm::dvec2& w) {
      return (v.x - u.x) * (w.y - u.y) - (v.y - u.y) * (w.x - u.x);
    };
    const double e0 = edge(pa, pb, q), e1 = edge(pb, pc, q), e2 = edge(pc, pa, q);
    const bool has_neg = e0 < 0 || e1 < 0 || e2<0, has_pos = e0> 0 || e1 > 0 || e2 > 0;
    if (has_neg && has_pos) continue;
    const double area = e0 + e1 + e2;
    if (area == 0.0) continue;
    const double x = (e1 * a.x + e2 * b.x + e0 * c.x) / area;
    if (x > p.x) ++crossings;
  }
  return crossings % 2 == 1;
}

bool inside_labels(const VolumeData& volume, int label, const glm::vec3& p) {
  const glm::dvec4 index = glm::inverse(volume.index_to_world) * glm::dvec4(glm::dvec3(p), 1.0);
  const glm::ivec3 v(std::lround(index.x), std::lround(index.y), std::lround(index.z));
  if (glm::any(glm::lessThan(v, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(v, volume.dims)))
    return false;
  return std::lround(volume.value_at(v.x, v.y, v.z)) == label;
}

}  // namespace

bool inside_region(const StreamlineRegion& region, const glm::vec3& p) {
  switch (region.shape) {
    case StreamlineRegion::Shape::sphere:
      return glm::distance(glm::dvec3(p), region.center) <= region.radius;
    case StreamlineRegion::Shape::label:
      return region.labels && inside_labels(*region.labels, region.label, p);
    case StreamlineRegion::Shape::mesh:
      return region.mesh && inside_mesh(*region.mesh, p);
  }
  return false;
}

std::vector<uint32_t> select_streamlines(const StreamlineObject& object) {
  const Streamlines& s = *object.streamlines;
  const size_t n = s.count();
  const size_t stride = static_cast<size_t>(std::max(object.stride, 1));
  std::vector<uint8_t> keep(n, 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const auto& range) {
    for (size_t i = range.begin(); i < range.end(); ++i) {
      if (i % stride != 0 || s.length(i) < 2) continue;
      const uint32_t a = s.offsets[i], b = s.offsets[i + 1];
      if (object.min_length > 0.0) {
        double length = 0.0;
        for (uint32_t p = a + 1; p < b; ++p) length += glm::distance(s.points[p - 1], s.points[p]);
        if (length < object.min_length) continue;
      }
      bool kept = true;
      for (const StreamlineRegion& region : object.regions) {
        bool touches = false;
        for (uint32_t p = a; p < b && !touches; ++p) touches = inside_region(region, s.points[p]);
        if (touches == region.avoid) {
          kept = false;
          break;
        }
      }
      keep[i] = kept;
    }
  });
  std::vector<uint32_t> selected;
  for (size_t i = 0; i < n; ++i)
    if (keep[i]) selected.push_back(static_cast<uint32_t>(i));
  return selected;
}

}  // namespace imx
