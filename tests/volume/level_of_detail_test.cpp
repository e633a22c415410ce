// Levels of detail: a pixel's footprint where a box lies, and a volume's next level (the means
// of 2x2x2 voxels, placed at their centre).
#include "volume/level_of_detail.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "intermix/error.hpp"

namespace imx {
namespace {

TEST(LevelOfDetail, APixelCoversMoreFartherAway) {
  Camera c;
  c.eye = glm::dvec3(0, -100, 0);
  c.target = glm::dvec3(0);
  c.fov_deg = 90.0;  // tan(45°) = 1: a pixel of a 200-row image is 1/100 of the depth
  const double near = pixel_footprint(c, 200, glm::dvec3(-10, -50, -10), glm::dvec3(10, 0, 10));
  const double far = pixel_footprint(c, 200, glm::dvec3(-10, 100, -10), glm::dvec3(10, 120, 10));
  EXPECT_NEAR(near, 0.5, 1e-12);  // the box's nearest face at depth 50
  EXPECT_NEAR(far, 2.0, 1e-12);   // at depth 200
  EXPECT_EQ(pixel_footprint(c, 200, glm::dvec3(-10, -200, -10), glm::dvec3(10, 0, 10)), 0.0);
  c.projection = Projection::orthographic;
  c.ortho_height = 300.0;
  EXPECT_DOUBLE_EQ(pixel_footprint(c, 200, glm::dvec3(0), glm::dvec3(1)), 1.5);
}

TEST(LevelOfDetail, TheNextLevelHoldsTheMeansOfEightVoxelsAtTheirCentre) {
  // 5 x 4 x 3 int16 with distinct values; an oblique, anisotropic placement.
  VolumeData fine;
  fine.dims = glm::ivec3(5, 4, 3);
  std::vector<int16_t> v(60);
  for (size_t n = 0; n < v.size(); ++n) v[n] = static_cast<int16_t>(n * n % 97 - 40);
  fine.voxels = VoxelBuffer<int16_t>(v);
  glm::dmat4 m = glm::rotate(glm::dmat4(1.0), 0.3, glm::dvec3(1, 2, 3));
  m = glm::scale(glm::translate(m, glm::dvec3(-7, 3, 11)), glm::dvec3(0.5, 0.7, 2.0));
  fine.index_to_world = m;
  const VolumeData coarse = halved(fine);
  ASSERT_EQ(coarse.dims, glm::ivec3(3, 2, 2));  // odd axes round up
  ASSERT_EQ(coarse.type(), VoxelType::i16);
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) {
        double sum = 0.0;
        glm::dvec3 centre(0.0);
        for (int c = 0; c < 8; ++c) {
          // The last voxel of an odd axis stands in for the missing one.
          const glm::ivec3 at(std::min(2 * i + (c & 1), 4), std::min(2 * j + (c >> 1 & 1), 3),
                              std::min(2 * k + (c >> 2 & 1), 2));
          sum += fine.value_at(at.x, at.y, at.z);
          centre += glm::dvec3(2 * i + (c & 1), 2 * j + (c >> 1 & 1), 2 * k + (c >> 2 & 1));
        }
        EXPECT_EQ(coarse.value_at(i, j, k), std::lround(sum / 8)) << i << j << k;
        // The coarse voxel's centre is the mean of its eight fine centres (before clamping).
        const glm::dvec3 want(fine.index_to_world * glm::dvec4(centre / 8.0, 1.0));
        const glm::dvec3 got(coarse.index_to_world * glm::dvec4(i, j, k, 1.0));
        EXPECT_NEAR(glm::length(want - got), 0.0, 1e-9) << i << j << k;
      }
  EXPECT_NEAR(longest_voxel_edge(coarse.index_to_world), 4.0, 1e-12);
}

TEST(LevelOfDetail, FloatMeansAreNotRoundedAndColourVolumesHaveNoLevel) {
  VolumeData fine;
  fine.dims = glm::ivec3(2, 2, 2);
  fine.voxels = VoxelBuffer<float>(std::vector<float>{0, 1, 0, 0, 0, 0, 0, 0});
  EXPECT_FLOAT_EQ(static_cast<float>(halved(fine).value_at(0, 0, 0)), 0.125f);
  fine.colours = std::make_shared<ColourVoxels>();
  EXPECT_THROW(halved(fine), Error);
}

}  // namespace
}  // namespace imx
