#include "phantoms/mesh_primitives.hpp"

#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "core/math.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"

namespace imx {
namespace {

void check_positive(double value, const char* what, const char* primitive) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw Error(fmt::format("{}: {} {} must be a positive finite number", primitive, what, value));
}

void check_segments(int segments, const char* primitive) {
  if (segments < 3 || segments > kMaxPrimitiveSegments)
    throw Error(fmt::format("{}: segments {} is not in [3, {}]", primitive, segments,
                            kMaxPrimitiveSegments));
}

// An empty mesh with room for the primitive's vertices and triangles, once the memory budget
// allows them (12 bytes a position, a normal and a triangle).
Mesh reserved_mesh(uint64_t vertices, uint64_t triangles, const char* primitive, int segments) {
  check_memory(24 * vertices + 12 * triangles,
               fmt::format("{}: segments {} ({} vertices, {} triangles)", primitive, segments,
                           vertices, triangles));
  Mesh mesh;
  mesh.positions.reserve(vertices);
  mesh.normals.reserve(vertices);
  mesh.triangles.reserve(triangles);
  return mesh;
}

// Unit circle points, computed once so that rings shared by several faces weld exactly.
std::vector<glm::dvec2> unit_circle(int segments) {
  std::vector<glm::dvec2> out(segments);
  for (int j = 0; j < segments; ++j) {
    double phi = 2.0 * std::numbers::pi * j / segments;
    out[j] = {std::cos(phi), std::sin(phi)};
  }
  return out;
}

uint32_t add_vertex(Mesh& mesh, const glm::dvec3& p, const glm::dvec3& n) {
  mesh.positions.emplace_back(p);
  mesh.normals.emplace_back(n);
  return static_cast<uint32_t>(mesh.positions.size() - 1);
}

void add_triangle(Mesh& mesh, uint32_t a, uint32_t b, uint32_t c) {
  mesh.triangles.push_back({a, b, c});
}

// A rectangle centred at `c` spanned by half-extents u and v, facing along u x v.
void add_rectangle(Mesh& mesh, const glm::dvec3& c, const glm::dvec3& u, const glm::dvec3& v) {
  glm::dvec3 n = glm::normalize(glm::cross(u, v));
  uint32_t i0 = add_vertex(mesh, c - u - v, n);
  uint32_t i1 = add_vertex(mesh, c + u - v, n);
  uint32_t i2 = add_vertex(mesh, c + u + v, n);
  uint32_t i3 = add_vertex(mesh, c - u + v, n);
  add_triangle(mesh, i0, i1, i2);
  add_triangle(mesh, i0, i2, i3);
}

}  // namespace

Mesh make_sphere(double radius, int segments) {
  check_positive(radius, "radius", "sphere");
  check_segments(segments, "sphere");
  const int rings = std::max(2, segments / 2);
  const uint64_t ring_vertices = static_cast<uint64_t>(rings - 1) * static_cast<uint64_t>(segments);
  Mesh mesh = reserved_mesh(2 + ring_vertices, 2 * ring_vertices, "sphere", segments);
  const std::vector<glm::dvec2> circle = unit_circle(segments);
  uint32_t north = add_vertex(mesh, {0.0, 0.0, radius}, {0.0, 0.0, 1.0});
  // Ring i (1..rings-1) at polar angle pi*i/rings; vertex (i, j) has index 1 + (i-1)*segments + j.
  for (int i = 1; i < rings; ++i) {
    double theta = std::numbers::pi * i / rings;
    double s = std::sin(theta), c = std::cos(theta);
    for (int j = 0; j < segments; ++j) {
      glm::dvec3 n(s * circle[j].x, s * circle[j].y, c);
      add_vertex(mesh, radius * n, n);
    }
  }
  uint32_t south = add_vertex(mesh, {0.0, 0.0, -radius}, {0.0, 0.0, -1.0});
  auto at = [segments](int i, int j) {
    return static_cast<uint32_t>(1 + (i - 1) * segments + (j % segments));
  };
  for (int j = 0; j < segments; ++j) {
    add_triangle(mesh, north, at(1, j), at(1, j + 1));
    for (int i = 1; i + 1 < rings; ++i) {
      add_triangle(mesh, at(i, j), at(i + 1, j), at(i + 1, j + 1));
      add_triangle(mesh, at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
    add_triangle(mesh, at(rings - 1, j), south, at(rings - 1, j + 1));
  }
  return mesh;
}

Mesh make_box(const glm::dvec3& size) {
  check_positive(size.x, "size x", "box");
  check_positive(size.y, "size y", "box");
  check_positive(size.z, "size z", "box");
  const glm::dvec3 h = 0.5 * size;
  const glm::dvec3 x(h.x, 0.0, 0.0), y(0.0, h.y, 0.0), z(0.0, 0.0, h.z);
  Mesh mesh;
  add_rectangle(mesh, x, y, z);   // +x
  add_rectangle(mesh, -x, z, y);  // -x
  add_rectangle(mesh, y, z, x);   // +y
  add_rectangle(mesh, -y, x, z);  // -y
  add_rectangle(mesh, z, x, y);   // +z
  add_rectangle(mesh, -z, y, x);  // -z
  return mesh;
}

Mesh make_cylinder(double radius, double height, int segments) {
  check_positive(radius, "radius", "cylinder");
  check_positive(height, "height", "cylinder");
  check_segments(segments, "cylinder");
  const uint32_t n = static_cast<uint32_t>(segments);
  Mesh mesh = reserved_mesh(4 * uint64_t{n} + 2, 4 * uint64_t{n}, "cylinder", segments);
  const std::vector<glm::dvec2> circle = unit_circle(segments);
  const double top = 0.5 * height, bottom = -0.5 * height;
  // Side: bottom ring at 2j, top ring at 2j + 1, radial normals.
  for (int j = 0; j < segments; ++j) {
    glm::dvec3 normal(circle[j], 0.0);
    add_vertex(mesh, {radius * circle[j], bottom}, normal);
    add_vertex(mesh, {radius * circle[j], top}, normal);
  }
  for (uint32_t j = 0; j < n; ++j) {
    uint32_t k = (j + 1) % n;
    add_triangle(mesh, 2 * j, 2 * k, 2 * k + 1);
    add_triangle(mesh, 2 * j, 2 * k + 1, 2 * j + 1);
  }
  // Caps: their own vertices, so that the rim stays sharp.
  for (int cap = 0; cap < 2; ++cap) {
    double z = cap == 0 ? top : bottom;
    glm::dvec3 normal(0.0, 0.0, cap == 0 ? 1.0 : -1.0);
    uint32_t centre = add_vertex(mesh, {0.0, 0.0, z}, normal);
    for (int j = 0; j < segments; ++j) add_vertex(mesh, {radius * circle[j], z}, normal);
    for (uint32_t j = 0; j < n; ++j) {
      uint32_t a = centre + 1 + j, b = centre + 1 + (j + 1) % n;
      if (cap == 0)
        add_triangle(mesh, centre, a, b);
      else
        add_triangle(mesh, centre, b, a);
    }
  }
  return mesh;
}

Mesh make_torus(double major_radius, double minor_radius, int segments) {
  check_positive(major_radius, "major radius", "torus");
  check_positive(minor_radius, "minor radius", "torus");
  check_segments(segments, "torus");
  if (minor_radius >= major_radius)
    throw Error(fmt::format("torus: minor radius {} must be less than the major radius {}",
                            minor_radius, major_radius));
  const int tube = std::max(3, segments / 2);
  const uint64_t cells = static_cast<uint64_t>(segments) * static_cast<uint64_t>(tube);
  Mesh mesh = reserved_mesh(cells, 2 * cells, "torus", segments);
  const std::vector<glm::dvec2> around = unit_circle(segments);
  const std::vector<glm::dvec2> section = unit_circle(tube);
  for (int i = 0; i < segments; ++i) {
    for (int j = 0; j < tube; ++j) {
      glm::dvec3 n(section[j].x * around[i].x, section[j].x * around[i].y, section[j].y);
      glm::dvec3 centre(major_radius * around[i], 0.0);
      add_vertex(mesh, centre + minor_radius * n, n);
    }
  }
  auto at = [segments, tube](int i, int j) {
    return static_cast<uint32_t>((i % segments) * tube + (j % tube));
  };
  for (int i = 0; i < segments; ++i) {
    for (int j = 0; j < tube; ++j) {
      add_triangle(mesh, at(i, j), at(i + 1, j), at(i + 1, j + 1));
      add_triangle(mesh, at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
  return mesh;
}

Mesh make_quad(const glm::dvec2& size) {
  check_positive(size.x, "size x", "quad");
  check_positive(size.y, "size y", "quad");
  Mesh mesh;
  add_rectangle(mesh, glm::dvec3(0.0), {0.5 * size.x, 0.0, 0.0}, {0.0, 0.5 * size.y, 0.0});
  return mesh;
}

Mesh transform_mesh(const Mesh& mesh, const glm::dmat4& m) {
  const glm::dmat3 linear(m);
  const double det = glm::determinant(linear);
  if (!all_finite(m) || !std::isfinite(det) || std::abs(det) < 1e-300)
    throw Error("transform_mesh: the transform is singular or not finite");
  const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
  Mesh out;
  out.positions.reserve(mesh.positions.size());
  for (const glm::vec3& p : mesh.positions)
    out.positions.emplace_back(transform_point(m, glm::dvec3(p)));
  out.normals.reserve(mesh.normals.size());
  for (const glm::vec3& n : mesh.normals) {
    glm::dvec3 t = normal_matrix * glm::dvec3(n);
    double len = glm::length(t);
    out.normals.emplace_back(len > 0.0 ? t / len : glm::dvec3(0.0));
  }
  out.colors = mesh.colors;
  out.triangles = mesh.triangles;
  if (det < 0.0)
    for (glm::uvec3& t : out.triangles) std::swap(t.y, t.z);
  return out;
}

}  // namespace imx
