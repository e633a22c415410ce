// The per-sample formulas on one float (ScalarOps); the lane tests hold the lanes to the same.
#include "volume/sample_formulas.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "random_volumes.hpp"
#include "volume/sample_ops.hpp"
#include "volume/voxel_grid.hpp"

namespace imx {
namespace {

TEST(SampleFormulas, TrilinearIsExactOnALinearField) {
  // f(x, y, z) = 1 + 2x + 3y + 5z at the corners of the unit cell, in c000, c100, ... order.
  float c[8];
  for (int k = 0; k < 8; ++k)
    c[k] = 1.0f + 2.0f * static_cast<float>(k & 1) + 3.0f * static_cast<float>((k >> 1) & 1) +
           5.0f * static_cast<float>(k >> 2);
  EXPECT_FLOAT_EQ(sample_formulas::trilinear<ScalarOps>(c, 0.25f, 0.5f, 0.75f),
                  1.0f + 0.5f + 1.5f + 3.75f);
  EXPECT_EQ(sample_formulas::trilinear<ScalarOps>(c, 0.0f, 0.0f, 0.0f), c[0]);
  EXPECT_EQ(sample_formulas::trilinear<ScalarOps>(c, 1.0f, 1.0f, 1.0f), c[7]);
}

TEST(SampleFormulas, LightComesFromTheMomentsMeanAndSpread) {
  float centre = 0.0f, spread = 0.0f;
  const float a = 0.8f, mean = 0.25f, sd = 0.1f;
  sample_formulas::light_of<ScalarOps>(a, a * mean, a * (mean * mean + sd * sd), centre, spread);
  EXPECT_NEAR(centre, mean, 1e-6f);
  EXPECT_NEAR(spread, sd, 1e-5f);
  // A mean past the piece's ends is clamped to them; a variance rounded below zero is no spread.
  sample_formulas::light_of<ScalarOps>(a, a * 1.5f, a * 0.9f, centre, spread);
  EXPECT_EQ(centre, 1.0f);
  EXPECT_EQ(spread, 0.0f);
  // A piece without opacity (or a NaN one): the midpoint, no spread.
  for (float none : {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN()}) {
    sample_formulas::light_of<ScalarOps>(none, 0.3f, 0.2f, centre, spread);
    EXPECT_EQ(centre, 0.5f) << none;
    EXPECT_EQ(spread, 0.0f) << none;
  }
}

// The marchers' gradient (the 32 voxels around p, rows clamped at the faces) against six clamped
// samples, at points inside the grid, faces included, on every voxel type.
template <class T>
void check_clamped_gradient(float scale) {
  std::mt19937 rng(11);
  const VolumeData vol = test::blob_volume<T>(glm::ivec3(9, 7, 6), rng, scale, 0.0f);
  const auto& voxels = std::get<VoxelBuffer<T>>(vol.voxels);
  const VoxelGrid<T> grid{voxels.data(), vol.dims};
  const glm::vec3 hi = glm::vec3(vol.dims) - 1.0f;
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  float worst = 0.0f;
  int at_faces = 0;
  for (int n = 0; n < 4000; ++n) {
    glm::vec3 p(u(rng), u(rng), u(rng));
    p *= hi;
    if (n % 4 == 0) p[n % 3] = n % 8 == 0 ? 0.0f : hi[n % 3];  // on a face
    if (glm::any(glm::lessThan(p, glm::vec3(1.0f))) || glm::any(glm::greaterThan(p, hi - 1.0f)))
      ++at_faces;
    const glm::vec3 d = grid.clamped_gradient(p) - grid.gradient(p);
    worst = std::max({worst, std::abs(d.x), std::abs(d.y), std::abs(d.z)});
  }
  EXPECT_GT(at_faces, 1000);
  EXPECT_LE(worst, 1e-4f * 255.0f * std::abs(scale)) << sizeof(T);
}

TEST(SampleFormulas, ClampedGradientIsSixClampedSamples) {
  check_clamped_gradient<uint8_t>(1.0f);
  check_clamped_gradient<int16_t>(-40.0f);
  check_clamped_gradient<uint16_t>(200.0f);
  check_clamped_gradient<float>(0.37f);
}

}  // namespace
}  // namespace imx
