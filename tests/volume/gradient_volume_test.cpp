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

}  // namespace
}  // namespace imx
