// LaneGrid against VoxelGrid on every SIMD target this machine runs (Highway's per-target test
// pattern): the lanes' trilinear samples, and their gradient against central differences of
// six samples.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "volume/lane_grid_test.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "random_volumes.hpp"
#include "volume/lane_grid-inl.hpp"

#ifndef IMX_LANE_GRID_TEST_ERRORS  // once, not per target
#define IMX_LANE_GRID_TEST_ERRORS
namespace imx {
// What the lanes found on one volume: the largest differences from VoxelGrid, relative to the
// volume's range, and how many packets had lanes near the faces.
struct LaneGridErrors {
  float sample = 0.0f, gradient = 0.0f;
  int near_faces = 0, packets = 0;
};
}  // namespace imx
#endif

HWY_BEFORE_NAMESPACE();
namespace imx::HWY_NAMESPACE {
namespace {

using namespace lanes;

template <class T>
LaneGridErrors lane_grid_errors_of(const VoxelGrid<T>& grid, uint32_t seed) {
  std::mt19937 rng(seed);
  const glm::vec3 hi = glm::vec3(grid.dims) - 1.0f;
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const LaneGrid<T> lanes(grid);
  LaneGridErrors e;
  for (int packet = 0; packet < 200; ++packet) {
    HWY_ALIGN float p[3][kLanes];
    // Mostly inside, some packets reaching the faces (clamped rows), a few outside.
    const float margin = packet % 5 == 0 ? -0.5f : 1.2f;
    for (int l = 0; l < kLanes; ++l)
      for (int a = 0; a < 3; ++a) p[a][l] = margin + u(rng) * (hi[a] - 2.0f * margin);
    const VF px = load(p[0]), py = load(p[1]), pz = load(p[2]);
    HWY_ALIGN float s[kLanes], g[3][kLanes];
    store(lanes.sample(px, py, pz), s);
    VF gx, gy, gz;
    ++e.packets;
    lanes.gradient(px, py, pz, gx, gy, gz);
    store(gx, g[0]), store(gy, g[1]), store(gz, g[2]);
    if (bits_of(lanes.lattice().interior(px, py, pz)) != kAllLanes) ++e.near_faces;
    for (int l = 0; l < kLanes; ++l) {
      const glm::vec3 q(p[0][l], p[1][l], p[2][l]);
      e.sample = std::max(e.sample, std::abs(s[l] - grid.sample(q)));
      // Outside the voxel centres the lanes clamp p before stepping a voxel either way.
      if (glm::any(glm::lessThan(q, glm::vec3(0.0f))) || glm::any(glm::greaterThan(q, hi)))
        continue;
      const glm::vec3 want = grid.gradient(q);
      for (int a = 0; a < 3; ++a) e.gradient = std::max(e.gradient, std::abs(g[a][l] - want[a]));
    }
  }
  return e;
}

void lane_grid_errors(const VolumeData& vol, uint32_t seed, LaneGridErrors& out) {
  std::visit(
      [&](const auto& voxels) HWY_ATTR {
        using T = typename std::decay_t<decltype(voxels)>::value_type;
        out = lane_grid_errors_of(VoxelGrid<T>{voxels.data(), vol.dims}, seed);
      },
      vol.voxels);
}

}  // namespace
}  // namespace imx::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "each_simd_target.hpp"

namespace imx {
namespace {

HWY_EXPORT(lane_grid_errors);

template <class T>
void check(float scale, uint32_t seed) {
  std::mt19937 rng(seed);
  const VolumeData vol = test::blob_volume<T>(glm::ivec3(23, 17, 19), rng, scale, 0.0f);
  const float range = 255.0f * std::abs(scale);
  test::for_each_simd_target([&](const std::string&) {
    LaneGridErrors e;
    HWY_DYNAMIC_DISPATCH(lane_grid_errors)(vol, seed, e);
    EXPECT_LE(e.sample, 1e-5f * range);
    // The fractions of p serve p +- 1: a rounding of p's apart.
    EXPECT_LE(e.gradient, 1e-4f * range);
    EXPECT_GT(e.near_faces, 0);          // packets reaching the faces, where rows are clamped
    EXPECT_LT(e.near_faces, e.packets);  // and packets wholly inside
  });
}

TEST(LaneGrid, SamplesAndInteriorGradientsMatchVoxelGridU8) {
  check<uint8_t>(1.0f, 3);
}
TEST(LaneGrid, SamplesAndInteriorGradientsMatchVoxelGridI16) {
  check<int16_t>(-7.0f, 4);
}
TEST(LaneGrid, SamplesAndInteriorGradientsMatchVoxelGridU16) {
  check<uint16_t>(200.0f, 5);
}
TEST(LaneGrid, SamplesAndInteriorGradientsMatchVoxelGridFloat) {
  check<float>(0.01f, 6);
}

}  // namespace
}  // namespace imx
#endif  // HWY_ONCE
