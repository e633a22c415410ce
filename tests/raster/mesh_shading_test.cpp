// Smooth shading and vertex colours of meshes read from files, measured on rasterized fragments.
#include <cmath>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include "intermix/io.hpp"
#include "phantoms/mesh_primitives.hpp"
#include "raster_test_util.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

constexpr double kRadius = 50.0;

// A UV sphere as an OBJ file of positions and faces only: normals are the reader's to make.
std::string sphere_obj(int segments) {
  const Mesh s = make_sphere(kRadius, segments);
  std::string out;
  for (const glm::vec3& p : s.positions) out += fmt::format("v {} {} {}\n", p.x, p.y, p.z);
  for (const glm::uvec3& t : s.triangles)
    out += fmt::format("f {} {} {}\n", t.x + 1, t.y + 1, t.z + 1);
  return out;
}

// Per pixel, the shading normal of the nearest fragment, recovered from six renders lit by one
// directional light along +-x, +-y, +-z (diffuse only: a channel is max(0, n.l)), and the
// true sphere normal where the pixel's ray meets the fragment. Returns the largest angle
// between them, in degrees, over pixels that see the sphere at less than 70 degrees.
double worst_normal_error_deg(const Mesh& mesh) {
  Scene scene = test::make_scene(64, 64);
  scene.camera.fov_deg = 12.0;
  Material material;
  material.shading = {true, 0.0f, 1.0f, 0.0f, 1.0f};
  test::add_mesh(scene, mesh, material);
  const CameraModel camera(scene.camera, 64, 64);
  const auto offsets = test::grid_offsets(1);
  std::vector<test::FrameFragments> lit;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {1.0, -1.0}) {
      glm::dvec3 to_light(0.0);
      to_light[axis] = sign;
      scene.lights = {Light{LightType::directional, -to_light, 1.0f, glm::vec3(1.0f)}};
      lit.push_back(test::rasterize_frame(Rasterizer(scene, camera, {}, 16), camera, offsets));
    }
  const double hh = std::tan(glm::radians(scene.camera.fov_deg) / 2.0);
  double worst = 0.0;
  int seen = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      if (lit[0].at(x, y, 0).empty()) continue;
      const glm::dvec3 eye = scene.camera.eye;
      const glm::dvec3 dir = glm::normalize(
          glm::dvec3((2.0 * (x + 0.5) / 64 - 1.0) * hh, 1.0, (1.0 - 2.0 * (y + 0.5) / 64) * hh));
      const glm::dvec3 hit = eye + double(lit[0].at(x, y, 0).front().t) * dir;
      const glm::dvec3 truth = glm::normalize(hit);
      if (glm::dot(truth, -dir) < std::cos(glm::radians(70.0))) continue;
      glm::dvec3 n;
      for (int axis = 0; axis < 3; ++axis)
        n[axis] = lit[2 * axis].at(x, y, 0).front().color.r -
                  lit[2 * axis + 1].at(x, y, 0).front().color.r;
      worst = std::max(
          worst,
          glm::degrees(std::acos(std::clamp(glm::dot(glm::normalize(n), truth), -1.0, 1.0))));
      ++seen;
    }
  EXPECT_GT(seen, 1000);
  return worst;
}

TEST(MeshShading, SphereFileWithoutNormalsShadesSmoothly) {
  test::TempDir dir;
  const auto file = dir.write("sphere.obj", sphere_obj(24));  // 15 degree facets
  const MeshFile smooth = read_mesh_file(file);
  ASSERT_FALSE(smooth.info.file_normals);
  MeshReadOptions faceted_options;
  faceted_options.crease_angle_deg = 0.0;  // every facet its own normal: flat shading
  const MeshFile faceted = read_mesh_file(file, faceted_options);
  const double smooth_error = worst_normal_error_deg(smooth.mesh);
  const double faceted_error = worst_normal_error_deg(faceted.mesh);
  std::printf("worst fragment normal error: smooth %.2f deg, faceted %.2f deg\n", smooth_error,
              faceted_error);
  EXPECT_LT(smooth_error, 2.0);
  EXPECT_GT(faceted_error, 5.0);
}

TEST(MeshShading, VertexColoursScaleTheMaterialColour) {
  // A quad facing the camera (-y), red on the left edge and blue on the right.
  Mesh quad = test::quad({-50, 0, -50}, {50, 0, -50}, {50, 0, 50}, {-50, 0, 50});
  quad.colors = {{1, 0, 0}, {0, 0, 1}, {0, 0, 1}, {1, 0, 0}};
  Scene scene = test::make_scene(32, 32, Projection::orthographic);
  scene.camera.ortho_height = 100.0;
  Material material;
  material.color = {0.5f, 1.0f, 1.0f};
  material.shading.enabled = false;
  test::add_mesh(scene, quad, material);
  const CameraModel camera(scene.camera, 32, 32);
  const auto offsets = test::grid_offsets(1);
  const test::FrameFragments f =
      test::rasterize_frame(Rasterizer(scene, camera, {}, 16), camera, offsets);
  ASSERT_EQ(f.at(0, 16, 0).size(), 1u);
  const glm::vec4 left = f.at(0, 16, 0).front().color, right = f.at(31, 16, 0).front().color,
                  middle = f.at(16, 16, 0).front().color;
  // x = (i + 0.5) / 32 of the way across: red fades linearly into blue.
  EXPECT_NEAR(left.r, 0.5f * (1.0f - 0.5f / 32), 1e-4f);
  EXPECT_NEAR(left.b, 0.5f / 32, 1e-4f);
  EXPECT_NEAR(right.b, 1.0f - 0.5f / 32, 1e-4f);
  EXPECT_NEAR(middle.r, 0.5f * (1.0f - 16.5f / 32), 1e-4f);
  EXPECT_NEAR(middle.g, 0.0f, 1e-6f);  // the material's green times colours without green
  EXPECT_FLOAT_EQ(middle.a, 1.0f);
}

}  // namespace
}  // namespace imx
