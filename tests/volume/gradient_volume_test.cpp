#include "volume/gradient_volume.hpp"

#include <gtest/gtest.h>

#include <random>

#include "random_volumes.hpp"

namespace imx {
namespace {

// Central differences are exact on a linear field, in the interior and (one-sided) at borders.
TEST(GradientVolume, IsExactOnLinearFieldsUpToQuantization) {
  VolumeData v;
  v.dims = {9, 7, 5};
  std::vector<float> f;
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 9; ++i) f.push_back(2.0f * i - 3.0f * j + 0.5f * k);
  v.voxels = std::move(f);
  GradientVolume g{AnyGrid(v)};
  for (glm::vec3 p : {glm::vec3(0), glm::vec3(4.3f, 2.7f, 1.1f), glm::vec3(8, 6, 4)}) {
    glm::vec3 d = g.sample(p);
    EXPECT_NEAR(d.x, 2.0f, 1e-3f);
    EXPECT_NEAR(d.y, -3.0f, 1e-3f);
    EXPECT_NEAR(d.z, 0.5f, 1e-3f);
  }
}

// In the interior, at voxel centres, it equals the on-the-fly gradient of the trilinear field.
TEST(GradientVolume, MatchesOnTheFlyGradientsAtVoxelCentres) {
  std::mt19937 rng(5);
  VolumeData v = test::blob_volume<int16_t>({20, 18, 16}, rng, 10.0f, -500.0f);
  AnyGrid grid(v);
  GradientVolume g(grid);
  float largest = 0.0f, worst = 0.0f;
  for (int k = 1; k < 15; ++k)
    for (int j = 1; j < 17; ++j)
      for (int i = 1; i < 19; ++i) {
        glm::vec3 p(i, j, k);
        glm::vec3 a = grid.gradient(p), b = g.sample(p);
        largest = std::max(largest, glm::length(a));
        worst = std::max(worst, glm::length(a - b));
      }
  ASSERT_GT(largest, 10.0f);
  EXPECT_LT(worst, 1e-4f * largest);
}

// Between voxel centres it is the trilinear blend of the eight voxel gradients around, up to the
// grid's far corner and on axes one voxel thick.
TEST(GradientVolume, InterpolatesTrilinearlyBetweenVoxels) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (glm::ivec3 dims : {glm::ivec3(6, 5, 4), glm::ivec3(5, 1, 3), glm::ivec3(1, 1, 4)}) {
    VolumeData v = test::blob_volume<int16_t>(dims, rng, 2.0f, -300.0f);
    GradientVolume g{AnyGrid(v)};
    auto at = [&](glm::ivec3 i) { return g.sample(glm::vec3(glm::min(i, dims - 1))); };
    for (int n = 0; n < 200; ++n) {
      glm::vec3 p = glm::vec3(unit(rng), unit(rng), unit(rng)) * glm::vec3(dims - 1);
      if (n == 0) p = glm::vec3(dims - 1);
      glm::ivec3 i0 = glm::min(glm::ivec3(p), glm::max(dims - 2, glm::ivec3(0)));
      glm::vec3 f = p - glm::vec3(i0);
      glm::vec3 expected(0.0f);
      for (int c = 0; c < 8; ++c) {
        glm::ivec3 o(c & 1, (c >> 1) & 1, (c >> 2) & 1);
        glm::vec3 w = glm::mix(1.0f - f, f, glm::vec3(o));
        expected += w.x * w.y * w.z * at(i0 + o);
      }
      glm::vec3 got = g.sample(p);
      for (int a = 0; a < 3; ++a)
        ASSERT_NEAR(got[a], expected[a], 1e-3f * (1.0f + std::abs(expected[a])))
            << "dims " << dims.x << "x" << dims.y << "x" << dims.z << " axis " << a;
    }
  }
}

}  // namespace
}  // namespace imx
