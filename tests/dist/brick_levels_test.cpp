// Levels of detail per brick: the level that fits a pixel's footprint, and the voxels of a coarse
// level that cover a brick of level 0.
#include "dist/brick_levels.hpp"

#include <cmath>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

namespace imx {
namespace {

// A pyramid of 1 mm voxels at level 0, each level half the last, level L's voxel i centred on
// level 0's index 2^L i + (2^L - 1) / 2 (the 2x2x2 means of the level below).
PyramidLevels pyramid(int levels, glm::ivec3 dims) {
  PyramidLevels p;
  for (int l = 0; l < levels; ++l) {
    const double s = std::ldexp(1.0, l);
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3((s - 1) / 2));
    p.index_to_world.push_back(glm::scale(m, glm::dvec3(s)));
    p.dims.push_back((dims + (1 << l) - 1) / (1 << l));
  }
  return p;
}

TEST(BrickLevels, TheLevelFittingAFootprintIsTheCoarsestNoLargerThanIt) {
  const PyramidLevels p = pyramid(4, glm::ivec3(64));
  EXPECT_EQ(level_fitting(p, 0.5), 0);  // finer than level 0: level 0 all the same
  EXPECT_EQ(level_fitting(p, 1.99), 0);
  EXPECT_EQ(level_fitting(p, 2.0), 1);
  EXPECT_EQ(level_fitting(p, 7.9), 2);
  EXPECT_EQ(level_fitting(p, 100.0), 3);  // the pyramid's coarsest
  // Anisotropic: the longest edge decides.
  PyramidLevels a = pyramid(2, glm::ivec3(64));
  a.index_to_world[1] = glm::scale(glm::dmat4(1.0), glm::dvec3(2.0, 2.0, 5.0));
  EXPECT_EQ(level_fitting(a, 4.0), 0);
  EXPECT_EQ(level_fitting(a, 5.0), 1);
}

TEST(BrickLevels, ACoarseBoxCoversTheBrickForTrilinearSampling) {
  const PyramidLevels p = pyramid(3, glm::ivec3(64, 64, 30));
  const VoxelBox brick{glm::ivec3(31, 0, 0), glm::ivec3(64, 64, 30)};
  for (int level = 1; level < 3; ++level) {
    const VoxelBox box = box_at_level(p, level, brick);
    // Every world point of the brick lies inside the box's voxel centres, a cell inside it.
    glm::dvec3 lo, hi;
    world_bounds(p, brick, lo, hi);
    const glm::dmat4 to_level = glm::inverse(p.index_to_world[static_cast<size_t>(level)]);
    const glm::dvec3 a(to_level * glm::dvec4(lo, 1.0)), b(to_level * glm::dvec4(hi, 1.0));
    for (int axis = 0; axis < 3; ++axis) {
      const int dim = p.dims[static_cast<size_t>(level)][axis];
      EXPECT_LE(box.lo[axis], std::max(0.0, std::floor(a[axis]))) << level << axis;
      EXPECT_GE(box.hi[axis] - 1, std::min(dim - 1.0, std::ceil(b[axis]))) << level << axis;
      EXPECT_GE(box.lo[axis], 0);
      EXPECT_LE(box.hi[axis], dim);
    }
    // And not the whole level: the brick's half along x.
    EXPECT_GT(box.lo.x, 0) << level;
  }
}

}  // namespace
}  // namespace imx
