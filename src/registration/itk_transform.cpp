// ITK's linear transform classes as matrices, by their documented parameter layouts.
#include <algorithm>
#include <cmath>
#include <initializer_list>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "registration/transform_readers.hpp"

namespace imx::detail {
namespace {

// "AffineTransform_double_3_3" -> "AffineTransform" when the rest is a 3-D double or float
// instance; empty when it is another dimension or precision.
std::string class_of(const std::string& type) {
  for (const char* suffix : {"_double_3_3", "_float_3_3"}) {
    const std::string s(suffix);
    if (type.size() > s.size() && type.compare(type.size() - s.size(), s.size(), s) == 0)
      return type.substr(0, type.size() - s.size());
  }
  return {};
}

glm::dmat3 rotation_x(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return glm::transpose(glm::dmat3(1, 0, 0, 0, c, -s, 0, s, c));  // rows given, GLM is by column
}
glm::dmat3 rotation_y(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return glm::transpose(glm::dmat3(c, 0, s, 0, 1, 0, -s, 0, c));
}
glm::dmat3 rotation_z(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return glm::transpose(glm::dmat3(c, -s, 0, s, c, 0, 0, 0, 1));
}

// The rotation of a versor given by its vector part (x, y, z); w = sqrt(1 - |v|^2) >= 0.
glm::dmat3 versor_matrix(double x, double y, double z, const std::string& what) {
  const double n2 = x * x + y * y + z * z;
  if (n2 > 1.0 + 1e-6)
    throw Error(
        fmt::format("{}: the versor's vector part ({}, {}, {}) has a norm above 1", what, x, y, z));
  const double w = std::sqrt(std::max(0.0, 1.0 - n2));
  const double rows[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                             {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                             {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
  glm::dmat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m[c][r] = rows[r][c];
  return m;
}

}  // namespace

glm::dmat4 itk_fixed_to_moving(const ItkTransform& t, const std::string& what) {
  const std::string kind = class_of(t.type);
  const std::vector<double>& p = t.parameters;
  auto expect = [&](size_t parameters, std::initializer_list<size_t> fixed) {
    if (p.size() != parameters)
      throw Error(
          fmt::format("{}: {} has {} parameters; it takes {}", what, t.type, p.size(), parameters));
    for (size_t n : fixed)
      if (t.fixed.size() == n) return;
    throw Error(fmt::format("{}: {} has {} fixed parameters; it takes {}", what, t.type,
                            t.fixed.size(), *fixed.begin()));
  };
  glm::dmat3 a(1.0);
  glm::dvec3 translation(0.0), centre(0.0);
  if (kind == "AffineTransform" || kind == "MatrixOffsetTransformBase" ||
      kind == "Rigid3DTransform") {
    expect(12, {3});
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a[c][r] = p[static_cast<size_t>(3 * r + c)];
    translation = {p[9], p[10], p[11]};
  } else if (kind == "Euler3DTransform") {
    expect(6, {3, 4});
    const bool zyx = t.fixed.size() == 4 && t.fixed[3] != 0.0;
    a = zyx ? rotation_z(p[2]) * rotation_y(p[1]) * rotation_x(p[0])
            : rotation_z(p[2]) * rotation_x(p[0]) * rotation_y(p[1]);
    translation = {p[3], p[4], p[5]};
  } else if (kind == "VersorRigid3DTransform") {
    expect(6, {3});
    a = versor_matrix(p[0], p[1], p[2], what);
    translation = {p[3], p[4], p[5]};
  } else if (kind == "Similarity3DTransform") {
    expect(7, {3});
    if (!(p[6] > 0.0))
      throw Error(fmt::format("{}: {}'s scale {} must be > 0", what, t.type, p[6]));
    a = p[6] * versor_matrix(p[0], p[1], p[2], what);
    translation = {p[3], p[4], p[5]};
  } else if (kind == "TranslationTransform") {
    expect(3, {0, 3});
    translation = {p[0], p[1], p[2]};
  } else if (kind == "IdentityTransform") {
    expect(0, {0, 3});
  } else {
    throw Error(fmt::format(
        "{}: unknown transform type '{}'; read are 3-D AffineTransform, "
        "MatrixOffsetTransformBase, Rigid3DTransform, Euler3DTransform, VersorRigid3DTransform, "
        "Similarity3DTransform, TranslationTransform and IdentityTransform (double or float), "
        "alone or in a CompositeTransform",
        what, t.type.substr(0, 80)));
  }
  if (t.fixed.size() >= 3 && kind != "TranslationTransform" && kind != "IdentityTransform")
    centre = {t.fixed[0], t.fixed[1], t.fixed[2]};
  // T(x) = A (x - c) + c + t = A x + (t + c - A c).
  glm::dmat4 m(a);
  const glm::dvec3 offset = translation + centre - a * centre;
  m[3] = glm::dvec4(offset, 1.0);
  return m;
}

}  // namespace imx::detail
