#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "random_volumes.hpp"
#include "volume/any_grid.hpp"
#include "volume/brick_min_max.hpp"
#include "volume/brick_occupancy.hpp"
#include "volume/tf_emptiness.hpp"
#include "volume/tf_lut.hpp"

namespace imx {
namespace {

// Trilinear sample positions filling brick b's closed region [b B, (b+1) B] within the hull
// [0, N-1] (written out here, not taken from BrickGrid): a quarter-voxel lattice that includes
// every voxel, face, edge and corner of it, plus random interior points.
template <class Fn>
void for_region_samples(const BrickGrid& g, glm::ivec3 b, std::mt19937& rng, Fn&& fn) {
  glm::ivec3 lo = b * g.size, hi = glm::min((b + 1) * g.size, g.voxel_dims - 1), n = 4 * (hi - lo);
  for (int k = 0; k <= n.z; ++k)
    for (int j = 0; j <= n.y; ++j)
      for (int i = 0; i <= n.x; ++i) fn(glm::vec3(lo) + 0.25f * glm::vec3(i, j, k));
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int s = 0; s < 200; ++s)
    fn(glm::vec3(lo) + 0.25f * glm::vec3(n) * glm::vec3(u(rng), u(rng), u(rng)));
}

TEST(BrickGrid, CountsBricksCoveringTheHull) {
  EXPECT_EQ(BrickGrid({256, 256, 256}, 8).dims, glm::ivec3(32));
  EXPECT_EQ(BrickGrid({257, 258, 9}, 8).dims, glm::ivec3(32, 33, 1));
  EXPECT_EQ(BrickGrid({1, 10, 2}, 8).dims, glm::ivec3(1, 2, 1));
  BrickGrid g({20, 20, 20}, 8);  // hull [0, 19]: bricks [0,8], [8,16], [16,19]
  EXPECT_EQ(g.dims, glm::ivec3(3));
  EXPECT_EQ(g.first_voxel({1, 1, 1}), glm::ivec3(8));
  EXPECT_EQ(g.last_voxel({1, 1, 1}), glm::ivec3(16));
  EXPECT_EQ(g.last_voxel({2, 2, 2}), glm::ivec3(19));
  EXPECT_EQ(g.brick_of({19.0f, 16.0f, 15.99f}), glm::ivec3(2, 2, 1));
  EXPECT_EQ(g.brick_of({-3.0f, 40.0f, 8.0f}), glm::ivec3(0, 2, 1));

  BrickGrid flat({512, 512, 28}, {8, 8, 1});  // one slice of cells a brick
  EXPECT_EQ(flat.dims, glm::ivec3(64, 64, 27));
  EXPECT_EQ(flat.last_voxel({1, 1, 26}), glm::ivec3(16, 16, 27));
  EXPECT_EQ(flat.brick_of({17.0f, 3.0f, 5.5f}), glm::ivec3(2, 0, 5));
}

TEST(BrickGrid, ShapesBricksAsNearCubesInMillimetres) {
  const glm::ivec3 kVoxels(256, 256, 100);
  EXPECT_EQ(BrickGrid::shape_for(8, {1.0, 1.0, 1.0}, kVoxels), glm::ivec3(8));
  EXPECT_EQ(BrickGrid::shape_for(8, {0.45, 0.45, 5.0}, kVoxels),
            glm::ivec3(8, 8, 1));  // 3.6 x 3.6 x 5 mm
  EXPECT_EQ(BrickGrid::shape_for(8, {0.49, 0.49, 2.62}, kVoxels), glm::ivec3(8, 8, 1));
  EXPECT_EQ(BrickGrid::shape_for(8, {2.0, 1.0, 1.5}, kVoxels), glm::ivec3(4, 8, 5));
  EXPECT_EQ(BrickGrid::shape_for(4, {3.0, 3.0, 1.0}, kVoxels), glm::ivec3(1, 1, 4));
  EXPECT_EQ(BrickGrid::shape_for(8, {1.0, 1.2, 1.0}, kVoxels), glm::ivec3(8, 7, 8));
  // Nothing to go by: a cube.
  EXPECT_EQ(BrickGrid::shape_for(8, {0.0, 1.0, 1.0}, kVoxels), glm::ivec3(8));
  EXPECT_EQ(BrickGrid::shape_for(8, {NAN, 1.0, 1.0}, kVoxels), glm::ivec3(8));
  EXPECT_EQ(BrickGrid::shape_for(8, {1.0, NAN, 1.0}, kVoxels), glm::ivec3(8));
  EXPECT_EQ(BrickGrid::shape_for(8, {1.0, INFINITY, 1.0}, kVoxels), glm::ivec3(8));
  // Too many bricks: twice the cells until the grid has at most kMaxBricks.
  const glm::ivec3 big(1024, 1024, 600);
  const glm::ivec3 shape = BrickGrid::shape_for(8, {0.2, 0.2, 2.0}, big);
  EXPECT_EQ(shape, glm::ivec3(16, 16, 2));
  EXPECT_LE(BrickGrid(big, shape).count(), BrickGrid::kMaxBricks);
  EXPECT_GT(BrickGrid(big, shape / 2).count(), BrickGrid::kMaxBricks);
  // Never larger than the grid needs.
  EXPECT_EQ(BrickGrid::shape_for(8, {1.0, 1.0, 1.0}, glm::ivec3(3, 2, 1)), glm::ivec3(8));
}

// Every trilinear sample inside a brick lies in its [min, max], and the bounds are attained
// there (tight: the voxel range is exactly what trilinear reads).
template <class T>
void check_min_max(glm::ivec3 dims, glm::ivec3 brick, float scale, float offset, uint32_t seed) {
  std::mt19937 rng(seed);
  VolumeData vol = test::blob_volume<T>(dims, rng, scale, offset);
  AnyGrid grid(vol);
  BrickMinMax mm(grid, brick, 2);
  const BrickGrid& g = mm.grid();
  for (int bz = 0; bz < g.dims.z; ++bz)
    for (int by = 0; by < g.dims.y; ++by)
      for (int bx = 0; bx < g.dims.x; ++bx) {
        glm::ivec3 b(bx, by, bz);
        glm::vec2 r = mm.range(b);
        float lo = INFINITY, hi = -INFINITY;
        for_region_samples(g, b, rng, [&](glm::vec3 p) {
          float v = grid.sample(p);
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        });
        // Trilinear blends of float data may round a few ulps past the voxel values.
        float tol = 1e-6f * std::max({1.0f, std::abs(r.x), std::abs(r.y)});
        ASSERT_GE(lo, r.x - tol) << "brick " << bx << "," << by << "," << bz;
        ASSERT_LE(hi, r.y + tol) << "brick " << bx << "," << by << "," << bz;
        // The lattice hits every voxel the brick reads, so the bounds are attained: tight.
        ASSERT_NEAR(lo, r.x, tol);
        ASSERT_NEAR(hi, r.y, tol);
      }
}

TEST(BrickMinMax, BoundsEveryTrilinearSampleAndIsTight) {
  check_min_max<uint8_t>({21, 18, 13}, glm::ivec3(4), 1.0f, 0.0f, 1);
  check_min_max<int16_t>({19, 25, 17}, glm::ivec3(8), 8.0f, -1024.0f, 2);
  check_min_max<float>({33, 9, 16}, glm::ivec3(8), 0.01f, -0.5f, 3);
  check_min_max<uint16_t>({8, 9, 10}, glm::ivec3(3), 100.0f, 0.0f, 4);
  check_min_max<int16_t>({23, 20, 9}, {8, 8, 1}, 8.0f, -1024.0f, 5);  // thick slices
  check_min_max<uint8_t>({17, 30, 12}, {2, 5, 3}, 1.0f, 0.0f, 6);
}

// No false "empty": wherever a brick is flagged empty, the classified samples are transparent.
template <class T>
void check_occupancy(glm::ivec3 dims, glm::ivec3 brick, float scale, float offset, uint32_t seed) {
  std::mt19937 rng(seed);
  VolumeData vol = test::blob_volume<T>(dims, rng, scale, offset);
  AnyGrid grid(vol);
  BrickMinMax mm(grid, brick, 2);
  const BrickGrid& g = mm.grid();
  int empty_total = 0;
  for (int trial = 0; trial < 6; ++trial) {
    TfLut lut(test::random_tf(rng, offset + 10.0f * scale, offset + 255.0f * scale));
    BrickOccupancy occ(mm, TfEmptiness(lut));
    for (int bz = 0; bz < g.dims.z; ++bz)
      for (int by = 0; by < g.dims.y; ++by)
        for (int bx = 0; bx < g.dims.x; ++bx) {
          glm::ivec3 b(bx, by, bz);
          if (occ.occupied(b)) continue;
          ++empty_total;
          for_region_samples(g, b, rng, [&](glm::vec3 p) {
            float v = grid.sample(p);
            ASSERT_EQ(lut.lookup(v).a, 0.0f)
                << "value " << v << " in empty brick " << bx << "," << by << "," << bz;
          });
        }
  }
  EXPECT_GT(empty_total, 0) << "the test never saw an empty brick";
}

TEST(BrickOccupancy, EmptyBricksHaveNoVisibleSample) {
  check_occupancy<uint8_t>({30, 27, 22}, glm::ivec3(4), 1.0f, 0.0f, 10);
  check_occupancy<int16_t>({26, 26, 26}, glm::ivec3(8), 8.0f, -1024.0f, 11);
  check_occupancy<float>({24, 20, 28}, glm::ivec3(4), 0.01f, -0.5f, 12);
  check_occupancy<int16_t>({30, 28, 10}, {8, 8, 1}, 8.0f, -1024.0f, 13);
}

}  // namespace
}  // namespace imx
