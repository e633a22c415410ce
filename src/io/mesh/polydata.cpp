#include "io/mesh/polydata.hpp"

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx::detail {
namespace {

uint32_t checked_vertex(int64_t v, uint64_t vertex_count, const std::string& what) {
  if (v < 0 || static_cast<uint64_t>(v) >= vertex_count)
    throw Error(
        fmt::format("{} uses vertex {}, but the file has {} points", what, v, vertex_count));
  return static_cast<uint32_t>(v);
}

}  // namespace

void add_polygon(Mesh& mesh, std::span<const int64_t> cell, uint64_t vertex_count,
                 const std::string& what) {
  if (cell.size() < 3)
    throw Error(fmt::format("{} has {} points, not 3 or more", what, cell.size()));
  const uint32_t first = checked_vertex(cell[0], vertex_count, what);
  for (size_t k = 1; k + 1 < cell.size(); ++k)
    mesh.triangles.emplace_back(first, checked_vertex(cell[k], vertex_count, what),
                                checked_vertex(cell[k + 1], vertex_count, what));
}

void add_strip(Mesh& mesh, std::span<const int64_t> cell, uint64_t vertex_count,
               const std::string& what) {
  if (cell.size() < 3)
    throw Error(fmt::format("{} has {} points, not 3 or more", what, cell.size()));
  for (size_t k = 0; k + 2 < cell.size(); ++k) {
    uint32_t a = checked_vertex(cell[k], vertex_count, what);
    uint32_t b = checked_vertex(cell[k + 1], vertex_count, what);
    const uint32_t c = checked_vertex(cell[k + 2], vertex_count, what);
    if (a == b || b == c || a == c) continue;
    if (k % 2 == 1) std::swap(a, b);
    mesh.triangles.emplace_back(a, b, c);
  }
}

}  // namespace imx::detail
