#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/gtc/matrix_access.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "volume/any_grid.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/voxel_grid.hpp"

namespace imx {
namespace {

VolumeData linear_field(glm::ivec3 dims, glm::vec4 coeff) {
  VolumeData v;
  v.dims = dims;
  std::vector<float> data;
  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i)
        data.push_back(coeff.x * i + coeff.y * j + coeff.z * k + coeff.w);
  v.voxels = std::move(data);
  return v;
}

TEST(VoxelGrid, TrilinearIsExactOnLinearFields) {
  VolumeData v = linear_field({7, 5, 9}, {1.5f, -2.0f, 0.25f, 3.0f});
  AnyGrid g(v);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> ux(0, 6), uy(0, 4), uz(0, 8);
  for (int n = 0; n < 1000; ++n) {
    glm::vec3 p(ux(rng), uy(rng), uz(rng));
    float expected = 1.5f * p.x - 2.0f * p.y + 0.25f * p.z + 3.0f;
    ASSERT_NEAR(g.sample(p), expected, 1e-4f) << p.x << "," << p.y << "," << p.z;
    glm::vec3 inner = glm::clamp(p, glm::vec3(1.0f), glm::vec3(5.0f, 3.0f, 7.0f));
    glm::vec3 grad = g.gradient(inner);
    ASSERT_NEAR(grad.x, 1.5f, 1e-4f);
    ASSERT_NEAR(grad.y, -2.0f, 1e-4f);
    ASSERT_NEAR(grad.z, 0.25f, 1e-4f);
  }
}

TEST(VoxelGrid, NativeTypesSampleTheSameValues) {
  VolumeData v8, v16;
  v8.dims = v16.dims = {2, 2, 2};
  v8.voxels = std::vector<uint8_t>{0, 10, 20, 30, 40, 50, 60, 200};
  v16.voxels = std::vector<int16_t>{0, 10, 20, 30, 40, 50, 60, 200};
  glm::vec3 p(0.25f, 0.5f, 0.75f);
  EXPECT_FLOAT_EQ(AnyGrid(v8).sample(p), AnyGrid(v16).sample(p));
  EXPECT_FLOAT_EQ(AnyGrid(v8).sample({1, 1, 1}), 200.0f);
  EXPECT_FLOAT_EQ(AnyGrid(v8).sample({0, 0, 0}), 0.0f);
}

TEST(PreparedVolume, IndexToWorldRoundTripsOnAnObliqueGrid) {
  VolumeData v = linear_field({10, 12, 8}, {1, 0, 0, 0});
  VolumeObject obj;
  obj.name = "oblique";
  obj.transfer_function.points = {{0.0, glm::vec4(0)}, {10.0, glm::vec4(1)}};
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(-20, 5, 12));
  m = glm::rotate(m, 0.4, glm::normalize(glm::dvec3(1, 2, 3)));
  m = glm::scale(m, glm::dvec3(0.7, 1.1, 2.5));
  obj.index_to_world = m;
  obj.data = std::make_shared<VolumeData>(v);
  PreparedVolume pv(obj);
  EXPECT_NEAR(pv.min_pitch, 0.7f, 1e-5f);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5, 15);
  for (int n = 0; n < 200; ++n) {
    glm::dvec3 idx(u(rng), u(rng), u(rng));
    glm::dvec3 world = glm::dvec3(m * glm::dvec4(idx, 1.0));
    glm::vec3 back = pv.to_index(glm::vec3(world));
    ASSERT_NEAR(back.x, idx.x, 1e-4);
    ASSERT_NEAR(back.y, idx.y, 1e-4);
    ASSERT_NEAR(back.z, idx.z, 1e-4);
  }
  // The world gradient of f = i is the first row of the inverse affine.
  glm::vec3 g = pv.world_gradient({5, 6, 4});
  glm::dvec3 expected = glm::dvec3(glm::row(glm::inverse(glm::dmat3(m)), 0));
  EXPECT_NEAR(g.x, expected.x, 1e-4);
  EXPECT_NEAR(g.y, expected.y, 1e-4);
  EXPECT_NEAR(g.z, expected.z, 1e-4);
}

TEST(PreparedVolume, RayIntervalCoversTheGridHullAndRespectsClipPlanes) {
  VolumeData v = linear_field({11, 11, 11}, {0, 0, 0, 1});
  VolumeObject obj;
  obj.name = "box";
  obj.transfer_function.points = {{0.0, glm::vec4(1)}};
  obj.index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-5.0));  // hull [-5, 5]^3
  obj.data = std::make_shared<VolumeData>(v);
  Ray ray{{0, -100, 0}, {0, 1, 0}};
  RayInterval r = PreparedVolume(obj).intersect(ray);
  EXPECT_NEAR(r.t0, 95.0f, 1e-4f);
  EXPECT_NEAR(r.t1, 105.0f, 1e-4f);
  obj.clip_planes.push_back({{0, 2, 0}, {0, -1, 0}});  // keep y <= 2
  r = PreparedVolume(obj).intersect(ray);
  EXPECT_NEAR(r.t1, 102.0f, 1e-4f);
  obj.clip_planes.push_back({{0, 3, 0}, {0, 1, 0}});  // and y >= 3: nothing left
  EXPECT_TRUE(PreparedVolume(obj).intersect(ray).empty());
  Ray miss{{20, -100, 0}, {0, 1, 0}};
  EXPECT_TRUE(PreparedVolume(obj).intersect(miss).empty());
}

}  // namespace
}  // namespace imx
