#include "io/mesh/gifti_reader.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/mesh/gifti_check.hpp"

namespace imx::detail {
namespace {

// Value i of an array, in this machine's byte order.
double value_at(const GiftiArray& a, size_t i) {
  return visit_gifti_type(a.type, [&]<class T>(T v) {
    uint8_t b[sizeof(T)];
    std::memcpy(b, a.bytes.data() + i * sizeof(T), sizeof(T));
    if (a.swapped) std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof(T));
    return static_cast<double>(v);
  });
}

// Element (row, col) of a rows x 3 array in the file's index order.
double element(const GiftiArray& a, size_t row, size_t col) {
  return value_at(a, a.column_major ? col * a.rows + row : row * 3 + col);
}

}  // namespace

Mesh read_gifti(const std::filesystem::path& file) {
  const GiftiSurface surface = read_gifti_arrays(file);
  const GiftiArray& points = surface.points;
  const GiftiArray& triangles = surface.triangles;
  Mesh mesh;
  mesh.positions.reserve(points.rows);
  for (size_t i = 0; i < points.rows; ++i)
    mesh.positions.emplace_back(element(points, i, 0), element(points, i, 1),
                                element(points, i, 2));
  mesh.triangles.reserve(triangles.rows);
  for (size_t f = 0; f < triangles.rows; ++f) {
    glm::uvec3 t;
    for (int c = 0; c < 3; ++c) {
      const double v = element(triangles, f, static_cast<size_t>(c));
      if (!(v >= 0.0 && v < static_cast<double>(points.rows)))
        throw Error(fmt::format("{}: triangle {} uses vertex {:.0f}, but the file has {} vertices",
                                file.string(), f, v, points.rows));
      t[c] = static_cast<uint32_t>(v);
    }
    mesh.triangles.push_back(t);
  }
  return mesh;
}

}  // namespace imx::detail
