// Displacement fields: a moving volume whose values are a linear function of position (which
// trilinear sampling reproduces exactly) resampled through constant and varying fields, against
// the value the field's definition gives, x -> x + d(x); refusals of fields of the wrong shape.
#include <cmath>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "registration/displacement_field.hpp"
#include "registration_files.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

// The moving volume: 24 x 20 x 16 voxels of 1.5 x 1.2 x 2 mm; its value at LPS point p is
// f(p) = 2 p.x - p.y + 0.5 p.z + 100.
double f(const glm::dvec3& p) {
  return 2 * p.x - p.y + 0.5 * p.z + 100;
}

VolumeData moving_volume() {
  VolumeData v;
  v.dims = {24, 20, 16};
  v.index_to_world = glm::dmat4(1.0);
  v.index_to_world[0][0] = 1.5;
  v.index_to_world[1][1] = 1.2;
  v.index_to_world[2][2] = 2.0;
  v.index_to_world[3] = glm::dvec4(-10, -8, -12, 1);
  std::vector<float> values;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 24; ++i)
        values.push_back(
            static_cast<float>(f(glm::dvec3(v.index_to_world * glm::dvec4(i, j, k, 1)))));
  v.voxels = VoxelBuffer<float>(std::move(values));
  return v;
}

// A field grid covering the moving volume and more: 2 mm voxels from (-20, -20, -20).
glm::dmat4 field_grid() {
  glm::dmat4 m(2.0);
  m[3] = glm::dvec4(-20, -20, -20, 1);
  return m;
}

TEST(DisplacementField, ConstantAndVaryingFieldsMoveTheValuesByTheirDefinition) {
  test::TempDir dir;
  const VolumeData moving = moving_volume();
  // d(x) = (3, -2, 1) + 0.05 x (linear in x, so trilinear sampling of it is exact).
  auto d_at = [](const glm::dvec3& x) { return glm::dvec3(3, -2, 1) + 0.05 * x; };
  const glm::dmat4 grid = field_grid();
  const auto file = dir.write(
      "warp.nii", test::displacement_field_nifti({24, 22, 20}, grid, [&](int i, int j, int k) {
        return d_at(glm::dvec3(grid * glm::dvec4(i, j, k, 1)));
      }));
  ASSERT_TRUE(is_displacement_field(file));
  double seconds = -1.0;
  const VolumeData warped = warp_volume(moving, file, &seconds);
  EXPECT_GE(seconds, 0.0);
  ASSERT_EQ(warped.dims, moving.dims);
  EXPECT_EQ(warped.type(), VoxelType::f32);
  int inside = 0, outside = 0;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 24; ++i) {
        const glm::dvec3 x = glm::dvec3(moving.index_to_world * glm::dvec4(i, j, k, 1));
        const glm::dvec3 y = x + d_at(x);
        const glm::dvec3 m = glm::dvec3(glm::inverse(moving.index_to_world) * glm::dvec4(y, 1));
        const bool in = m.x >= 0 && m.y >= 0 && m.z >= 0 && m.x <= 23 && m.y <= 19 && m.z <= 15;
        const double got = warped.value_at(i, j, k);
        if (in) {
          ++inside;
          EXPECT_NEAR(got, f(y), 2e-3) << i << " " << j << " " << k;
        } else {
          ++outside;
          EXPECT_TRUE(std::isnan(got)) << i << " " << j << " " << k;
        }
      }
  EXPECT_GT(inside, 3000);
  EXPECT_GT(outside, 100);
}

TEST(DisplacementField, OutsideTheFieldNothingMoves) {
  test::TempDir dir;
  const VolumeData moving = moving_volume();
  // A small field around the origin only: beyond it the displacement is zero, as ITK's.
  glm::dmat4 grid(1.0);
  grid[3] = glm::dvec4(-2, -2, -2, 1);
  const auto file = dir.write(
      "small.nii", test::displacement_field_nifti(
                       {5, 5, 5}, grid, [](int, int, int) { return glm::dvec3(1, 1, 1); }));
  const VolumeData warped = warp_volume(moving, file);
  // Voxel (20, 15, 12) lies at (20, 10, 12) mm, far outside the field: unchanged.
  EXPECT_NEAR(warped.value_at(20, 15, 12), moving.value_at(20, 15, 12), 1e-4);
}

TEST(DisplacementField, WrongShapesAreRefused) {
  test::TempDir dir;
  const VolumeData moving = moving_volume();
  const auto plain = dir.write(
      "vec.nii", test::displacement_field_nifti(
                     {4, 4, 4}, field_grid(), [](int, int, int) { return glm::dvec3(0.0); }, 0));
  EXPECT_FALSE(is_displacement_field(plain));
  test::expect_error([&] { warp_volume(moving, plain); }, {"vec.nii", "not a displacement field"});
  write_volume(moving, dir / "plain.nii", false);
  EXPECT_FALSE(is_displacement_field(dir / "plain.nii"));
}

}  // namespace
}  // namespace imx
