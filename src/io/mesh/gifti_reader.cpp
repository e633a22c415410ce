#include "io/mesh/gifti_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <glm/glm.hpp>

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

std::string trimmed(const std::string& text) {
  const size_t b = text.find_first_not_of(" \t\r\n"), e = text.find_last_not_of(" \t\r\n");
  return b == std::string::npos ? std::string() : text.substr(b, e - b + 1);
}

// MatrixData: 16 finite numbers, row after row, the last row 0 0 0 1 (an affine map).
glm::dmat4 parse_matrix(const std::filesystem::path& file, const std::string& text) {
  std::vector<double> v;
  const char* p = text.c_str();
  while (*p != '\0' && v.size() <= 16) {
    char* end = nullptr;
    const double x = std::strtod(p, &end);
    if (end == p) break;
    v.push_back(x);
    p = end;
  }
  while (*p != '\0' && std::isspace(static_cast<unsigned char>(*p))) ++p;
  if (v.size() != 16 || *p != '\0' ||
      !std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }))
    throw Error(fmt::format(
        "{}: the vertices' CoordinateSystemTransformMatrix is not 16 finite numbers: '{}'",
        file.string(), trimmed(text).substr(0, 80)));
  if (std::abs(v[12]) > 1e-6 || std::abs(v[13]) > 1e-6 || std::abs(v[14]) > 1e-6 ||
      std::abs(v[15] - 1.0) > 1e-6)
    throw Error(
        fmt::format("{}: the vertices' CoordinateSystemTransformMatrix's last row is {:g} "
                    "{:g} {:g} {:g}, not 0 0 0 1",
                    file.string(), v[12], v[13], v[14], v[15]));
  glm::dmat4 m(1.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = v[static_cast<size_t>(4 * r + c)];  // glm: m[column]
  return m;
}

bool near_identity(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (std::abs(m[c][r] - (c == r ? 1.0 : 0.0)) > 1e-9) return false;
  return true;
}

// Places the vertices by the first coordinate system that maps an anatomical space other than the
// scanner's (NIFTI_XFORM_UNKNOWN or _ALIGNED_ANAT: FreeSurfer's tkr-RAS) to
// NIFTI_XFORM_SCANNER_ANAT, the space NIfTI volumes' sform and qform place voxels in; others are
// named in a note.
void place_by_coordinate_system(const std::filesystem::path& file, const GiftiSurface& surface,
                                Mesh& mesh, std::vector<std::string>* notes) {
  const std::string shown = file.filename().string();
  bool placed = false;
  for (const GiftiCoordinateSystem& c : surface.coordinate_systems) {
    const std::string from = trimmed(c.data_space), to = trimmed(c.transformed_space);
    if (trimmed(c.matrix).empty()) continue;
    const glm::dmat4 m = parse_matrix(file, c.matrix);
    if (from == to || near_identity(m)) continue;
    const bool moves = !placed && to == "NIFTI_XFORM_SCANNER_ANAT" &&
                       (from == "NIFTI_XFORM_UNKNOWN" || from == "NIFTI_XFORM_ALIGNED_ANAT");
    if (moves) {
      for (glm::vec3& p : mesh.positions) p = glm::vec3(m * glm::dvec4(glm::dvec3(p), 1.0));
      placed = true;
    }
    if (notes != nullptr)
      notes->push_back(
          moves ? fmt::format("{}: GIfTI vertices in {} (DataSpace), moved to {} by the file's "
                              "CoordinateSystemTransformMatrix (translation {:g} {:g} {:g} mm)",
                              shown, from, to, m[3][0], m[3][1], m[3][2])
                : fmt::format("{}: the file's CoordinateSystemTransformMatrix maps {} to {}; the "
                              "vertices stay in their DataSpace, {}",
                              shown, from.empty() ? "(no DataSpace)" : from,
                              to.empty() ? "(no TransformedSpace)" : to, from));
  }
}

}  // namespace

Mesh read_gifti(const std::filesystem::path& file, std::vector<std::string>* notes) {
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
  place_by_coordinate_system(file, surface, mesh, notes);
  return mesh;
}

}  // namespace imx::detail
