#include <cmath>

#include <gtest/gtest.h>

#include "core/math.hpp"
#include "expect_error.hpp"
#include "intermix/io.hpp"

namespace imx {
namespace {

using test::expect_error;

// The value of the voxel whose centre is nearest to world point p.
double value_near(const VolumeData& v, const glm::dvec3& p) {
  glm::dvec3 idx = transform_point(glm::inverse(v.index_to_world), p);
  glm::ivec3 i = glm::clamp(glm::ivec3(glm::round(idx)), glm::ivec3(0), v.dims - 1);
  return v.value_at(i.x, i.y, i.z);
}

glm::dvec3 world_centre(const VolumeData& v) {
  return transform_point(v.index_to_world, 0.5 * glm::dvec3(v.dims - 1));
}

TEST(Phantoms, NamesAreListed) {
  std::vector<std::string> names = phantom_names();
  for (const char* n : {"ct-head", "cube", "ellipsoid", "pet", "shells", "sphere"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
}

TEST(Phantoms, EveryPhantomIsValidCentredAndSized) {
  for (const std::string& name : phantom_names())
    for (int size : {8, 33, 64}) {
      VolumeData v = make_phantom(name, size);
      SCOPED_TRACE(name + " size " + std::to_string(size));
      EXPECT_NO_THROW(v.validate(name));
      int largest = std::max({v.dims.x, v.dims.y, v.dims.z});
      EXPECT_EQ(largest, name == "pet" ? std::max(8, size / 4) : size);
      EXPECT_LT(glm::length(world_centre(v)), 1e-9);
      auto [lo, hi] = v.range();
      EXPECT_LT(lo, hi);
    }
}

TEST(Phantoms, AreDeterministic) {
  for (const std::string& name : phantom_names()) {
    VolumeData a = make_phantom(name, 40), b = make_phantom(name, 40);
    EXPECT_TRUE(a.voxels == b.voxels) << name;
    EXPECT_EQ(a.index_to_world, b.index_to_world) << name;
  }
}

TEST(Phantoms, BadNameOrSizeThrows) {
  expect_error([] { make_phantom("teapot", 64); }, {"teapot", "ct-head", "shells"});
  expect_error([] { make_phantom("cube", 7); }, {"cube", "size 7"});
  expect_error([] { make_phantom("cube", 1025); }, {"size 1025"});
  expect_error([] { make_phantom("ct-head", -3); }, {"size -3"});
}

TEST(CtHead, TissueValuesAndGeometry) {
  VolumeData v = make_phantom("ct-head", 128);
  ASSERT_EQ(v.type(), VoxelType::i16);
  glm::dvec3 s = v.spacing();
  EXPECT_NEAR(s.x, 1.8, 1e-9);
  EXPECT_NEAR(s.y, 1.8, 1e-9);
  EXPECT_NEAR(s.z, 2.4, 1e-9);  // thicker slices, as in a clinical CT
  EXPECT_EQ(v.value_at(0, 0, 0), -1000.0);
  EXPECT_EQ(v.value_at(v.dims.x - 1, v.dims.y - 1, v.dims.z - 1), -1000.0);
  EXPECT_NEAR(value_near(v, {0, 0, 0}), 30.0, 1.0);       // brain
  EXPECT_NEAR(value_near(v, {9, 2, 15}), 5.0, 1.0);       // a ventricle
  EXPECT_EQ(value_near(v, {0, 4, 95}), -1000.0);          // above the vertex
  EXPECT_NEAR(value_near(v, {0, 4, 88}), 40.0, 5.0);      // scalp
  EXPECT_NEAR(value_near(v, {0, 4, -110}), 40.0, 1.0);    // neck, in the bottom slice
  EXPECT_NEAR(value_near(v, {0, 28, -100}), 900.0, 5.0);  // cervical spine
  EXPECT_NEAR(value_near(v, {32, -70, -8}), 10.0, 2.0);   // an eyeball
  EXPECT_NEAR(value_near(v, {0, -96, -22}), 40.0, 2.0);   // the nose
  auto [lo, hi] = v.range();
  EXPECT_EQ(lo, -1000.0);
  EXPECT_EQ(hi, 1500.0);
}

TEST(CtHead, SkullHasDenseTablesAroundDiploe) {
  VolumeData v = make_phantom("ct-head", 256);
  // Along +x from the centre: brain, inner table, diploe, outer table, scalp, air.
  auto at_x = [&](double x) { return value_near(v, {x, 4.0, 0.0}); };
  EXPECT_NEAR(at_x(50.0), 30.0, 1.0);
  EXPECT_GT(at_x(65.0), 1200.0);
  EXPECT_NEAR(at_x(67.5), 700.0, 150.0);
  EXPECT_GT(at_x(70.0), 1200.0);
  EXPECT_NEAR(at_x(73.0), 40.0, 5.0);
  EXPECT_EQ(at_x(85.0), -1000.0);
}

TEST(CtHead, EdgesBlendOverAboutOneVoxel) {
  VolumeData v = make_phantom("ct-head", 128);
  // Walk out of the head along -z (superior is +z) and count intermediate voxels at the skin.
  int i = v.dims.x / 2, j = v.dims.y / 2, partial = 0;
  for (int k = v.dims.z - 1; k >= 0; --k) {
    double value = v.value_at(i, j, k);
    if (value == -1000.0) continue;
    if (value > -990.0 && value < 30.0) ++partial;
    if (value >= 30.0) break;
  }
  EXPECT_GE(partial, 1);
  EXPECT_LE(partial, 2);
}

TEST(Cube, SolidCentreEmptyCornersSoftEdges) {
  VolumeData v = make_phantom("cube", 64);
  ASSERT_EQ(v.type(), VoxelType::u8);
  EXPECT_EQ(v.dims, glm::ivec3(64));
  EXPECT_EQ(value_near(v, {0, 0, 0}), 255.0);
  EXPECT_EQ(v.value_at(0, 0, 0), 0.0);
  EXPECT_EQ(value_near(v, {35, -35, 35}), 255.0);
  EXPECT_EQ(value_near(v, {42, 0, 0}), 0.0);
  // The fraction of full voxels is about 0.6^3 of the grid.
  const auto& vox = std::get<VoxelBuffer<uint8_t>>(v.voxels);
  double inside = 0;
  for (uint8_t x : vox) inside += x / 255.0;
  EXPECT_NEAR(inside / vox.size(), 0.216, 0.01);
}

TEST(Ellipsoid, HasItsOwnSpacingAndSemiAxes) {
  VolumeData e = make_phantom("ellipsoid", 128), c = make_phantom("cube", 128);
  EXPECT_NEAR(e.spacing().x, 0.8, 1e-12);
  EXPECT_NEAR(c.spacing().x, 1.0, 1e-12);
  EXPECT_EQ(value_near(e, {0, 0, 0}), 255.0);
  EXPECT_EQ(value_near(e, {43, 0, 0}), 255.0);
  EXPECT_EQ(value_near(e, {47, 0, 0}), 0.0);
  EXPECT_EQ(value_near(e, {0, 28, 0}), 255.0);
  EXPECT_EQ(value_near(e, {0, 32, 0}), 0.0);
  EXPECT_EQ(value_near(e, {0, 0, 33}), 255.0);
  EXPECT_EQ(value_near(e, {0, 0, 37}), 0.0);
}

TEST(Pet, RotatedCoarseGridWithHotSpots) {
  VolumeData v = make_phantom("pet", 256);
  ASSERT_EQ(v.type(), VoxelType::f32);
  EXPECT_EQ(v.dims.y, 64);
  EXPECT_NEAR(v.spacing().x, 3.6, 1e-9);  // four times ct-head's 0.9 mm at size 256
  glm::dmat3 linear(v.index_to_world);
  glm::dmat3 direction = linear / 3.6;
  EXPECT_GT(glm::length(direction[0] - glm::dvec3(1, 0, 0)), 0.1) << "grid must be rotated";
  EXPECT_NEAR(glm::determinant(direction), 1.0, 1e-9);
  EXPECT_EQ(v.value_at(0, 0, 0), 0.0);
  EXPECT_NEAR(value_near(v, {0, 4, 0}), 2.0, 0.1);   // brain away from the hot spots
  EXPECT_NEAR(value_near(v, {0, 4, 86}), 1.0, 0.3);  // scalp and skull band
  auto [lo, hi] = v.range();
  EXPECT_EQ(lo, 0.0);
  EXPECT_GT(hi, 8.0);
  EXPECT_LT(hi, 12.5);
}

TEST(Shells, RayThroughTheCentreCrossesSixteenWalls) {
  VolumeData v = make_phantom("shells", 256);
  ASSERT_EQ(v.type(), VoxelType::f32);
  int j = v.dims.y / 2, k = v.dims.z / 2, walls = 0;
  bool in_wall = false;
  std::vector<double> peaks;
  double peak = 0.0;
  for (int i = 0; i < v.dims.x; ++i) {
    double value = v.value_at(i, j, k);
    if (value > 1.0 && !in_wall) ++walls;
    if (value > 1.0) peak = std::max(peak, value);
    if (value <= 1.0 && in_wall) peaks.push_back(peak), peak = 0.0;
    in_wall = value > 1.0;
  }
  EXPECT_EQ(walls, 16);
  ASSERT_EQ(peaks.size(), 16u);
  for (int w = 0; w < 8; ++w) {
    EXPECT_NEAR(peaks[w], 10.0 * (8 - w), 1.0);  // outermost first
    EXPECT_NEAR(peaks[15 - w], 10.0 * (8 - w), 1.0);
  }
}

TEST(Sphere, IsASignedDistance) {
  VolumeData v = make_phantom("sphere", 64);
  ASSERT_EQ(v.type(), VoxelType::f32);
  for (int k = 0; k < v.dims.z; k += 7)
    for (int j = 0; j < v.dims.y; j += 5)
      for (int i = 0; i < v.dims.x; i += 3) {
        glm::dvec3 p = transform_point(v.index_to_world, glm::dvec3(i, j, k));
        EXPECT_NEAR(v.value_at(i, j, k), 0.35 * 128.0 - glm::length(p), 1e-4);
      }
}

}  // namespace
}  // namespace imx
