#include "phantoms/mesh_primitives.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "expect_error.hpp"
#include "mesh_checks.hpp"

namespace imx {
namespace {

using test::error_of;
using test::is_closed_and_oriented;
using test::signed_volume;

// Every vertex normal is unit length and agrees with the faces that use it.
void expect_good_normals(const Mesh& mesh) {
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  for (const glm::vec3& n : mesh.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
  for (const glm::uvec3& t : mesh.triangles) {
    glm::vec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
    glm::vec3 face = glm::cross(b - a, c - a);
    for (uint32_t i : {t.x, t.y, t.z}) ASSERT_GT(glm::dot(face, mesh.normals[i]), 0.0f);
  }
}

void expect_closed(const Mesh& mesh) {
  std::string why;
  EXPECT_TRUE(is_closed_and_oriented(mesh, &why)) << why;
}

TEST(MeshPrimitives, SphereIsClosedOutwardAndHasTheRightVolume) {
  Mesh m = make_sphere(10.0, 64);
  expect_closed(m);
  expect_good_normals(m);
  double exact = 4.0 / 3.0 * std::numbers::pi * 1000.0;
  EXPECT_NEAR(signed_volume(m), exact, 0.02 * exact);
  for (const glm::vec3& p : m.positions) EXPECT_NEAR(glm::length(p), 10.0f, 1e-4f);
}

TEST(MeshPrimitives, CoarseSphereIsStillClosed) {
  Mesh m = make_sphere(1.0, 3);
  expect_closed(m);
  EXPECT_GT(signed_volume(m), 0.0);
}

TEST(MeshPrimitives, BoxIsClosedOutwardWithFlatNormals) {
  Mesh m = make_box({2.0, 3.0, 4.0});
  expect_closed(m);
  expect_good_normals(m);
  EXPECT_EQ(m.triangles.size(), 12u);
  EXPECT_NEAR(signed_volume(m), 24.0, 1e-9);
  for (const glm::vec3& p : m.positions) {
    EXPECT_FLOAT_EQ(std::abs(p.x), 1.0f);
    EXPECT_FLOAT_EQ(std::abs(p.z), 2.0f);
  }
}

TEST(MeshPrimitives, CylinderIsClosedOutwardAndHasTheRightVolume) {
  Mesh m = make_cylinder(5.0, 20.0, 64);
  expect_closed(m);
  expect_good_normals(m);
  double exact = std::numbers::pi * 25.0 * 20.0;
  EXPECT_NEAR(signed_volume(m), exact, 0.02 * exact);
  for (const glm::vec3& p : m.positions) EXPECT_LE(std::abs(p.z), 10.0f + 1e-5f);
}

TEST(MeshPrimitives, TorusIsClosedOutwardAndHasTheRightVolume) {
  Mesh m = make_torus(20.0, 5.0, 64);
  expect_closed(m);
  expect_good_normals(m);
  double exact = 2.0 * std::numbers::pi * std::numbers::pi * 20.0 * 25.0;
  EXPECT_NEAR(signed_volume(m), exact, 0.02 * exact);
}

TEST(MeshPrimitives, QuadLiesInZZeroFacingPlusZ) {
  Mesh m = make_quad({4.0, 2.0});
  ASSERT_EQ(m.triangles.size(), 2u);
  expect_good_normals(m);
  double area = 0.0;
  for (const glm::uvec3& t : m.triangles) {
    glm::dvec3 a(m.positions[t.x]), b(m.positions[t.y]), c(m.positions[t.z]);
    area += 0.5 * glm::cross(b - a, c - a).z;  // positive: counter-clockwise seen from +z
  }
  EXPECT_NEAR(area, 8.0, 1e-9);
  for (const glm::vec3& p : m.positions) {
    EXPECT_EQ(p.z, 0.0f);
    EXPECT_FLOAT_EQ(std::abs(p.x), 2.0f);
    EXPECT_FLOAT_EQ(std::abs(p.y), 1.0f);
  }
  for (const glm::vec3& n : m.normals) EXPECT_EQ(n, glm::vec3(0.0f, 0.0f, 1.0f));
}

TEST(MeshPrimitives, BadParametersAreErrors) {
  EXPECT_NE(error_of([] { make_sphere(0.0, 16); }), "(no error)");
  EXPECT_NE(error_of([] { make_sphere(1.0, 2); }), "(no error)");
  EXPECT_NE(error_of([] { make_box({1.0, -1.0, 1.0}); }), "(no error)");
  EXPECT_NE(error_of([] { make_cylinder(1.0, std::nan(""), 16); }), "(no error)");
  EXPECT_NE(error_of([] { make_torus(1.0, 2.0, 16); }), "(no error)");
  EXPECT_NE(error_of([] { make_quad({0.0, 1.0}); }), "(no error)");
}

TEST(TransformMesh, MovesPointsAndScalesVolume) {
  Mesh box = make_box(glm::dvec3(2.0));
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(10.0, 0.0, 0.0)) *
                 glm::scale(glm::dmat4(1.0), glm::dvec3(1.0, 2.0, 3.0));
  Mesh out = transform_mesh(box, m);
  EXPECT_NEAR(signed_volume(out), 8.0 * 6.0, 1e-6);
  for (const glm::vec3& p : out.positions) EXPECT_NEAR(std::abs(p.x - 10.0f), 1.0f, 1e-5f);
  expect_closed(out);
  expect_good_normals(out);
}

TEST(TransformMesh, NormalsUseTheInverseTranspose) {
  Mesh sphere = make_sphere(1.0, 32);
  glm::dvec3 s(1.0, 2.0, 4.0);
  Mesh out = transform_mesh(sphere, glm::scale(glm::dmat4(1.0), s));
  for (size_t i = 0; i < out.positions.size(); ++i) {
    // The ellipsoid x²/a² + ... = 1 has gradient (x/a², y/b², z/c²).
    glm::dvec3 p(out.positions[i]);
    glm::dvec3 expected = glm::normalize(p / (s * s));
    EXPECT_GT(glm::dot(expected, glm::dvec3(out.normals[i])), 0.9999);
  }
}

TEST(TransformMesh, MirroringKeepsTheWindingOutward) {
  Mesh out = transform_mesh(make_sphere(1.0, 32), glm::scale(glm::dmat4(1.0), {-1.0, 1.0, 1.0}));
  EXPECT_GT(signed_volume(out), 0.0);
  expect_closed(out);
  expect_good_normals(out);
}

TEST(TransformMesh, SingularTransformIsAnError) {
  EXPECT_NE(error_of([] { transform_mesh(make_quad({1.0, 1.0}), glm::dmat4(0.0)); }), "(no error)");
}

}  // namespace
}  // namespace imx
