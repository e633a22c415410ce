// The parallel set-up of large meshes: the same fragments at any thread count, and triangles
// the set-up no longer refuses itself (degenerate, edge-on) still make none.
#include <cstring>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "raster_test_util.hpp"

namespace imx {
namespace {

using test::FrameFragments;

void expect_same(const FrameFragments& a, const FrameFragments& b) {
  ASSERT_EQ(a.samples.size(), b.samples.size());
  size_t fragments = 0;
  for (size_t i = 0; i < a.samples.size(); ++i) {
    ASSERT_EQ(a.samples[i].size(), b.samples[i].size()) << "sample " << i;
    fragments += a.samples[i].size();
    if (a.samples[i].empty()) continue;
    ASSERT_EQ(std::memcmp(a.samples[i].data(), b.samples[i].data(),
                          a.samples[i].size() * sizeof(Fragment)),
              0)
        << "sample " << i;
  }
  EXPECT_GT(fragments, 1000u);
}

TEST(MeshSetup, AMeshOfOverAMillionTrianglesGivesTheSameFragmentsOnOneThread) {
  Scene scene = test::make_scene(120, 90);
  test::add_mesh(scene, test::sphere({0, 0, 0}, 60, 720, 800));  // > 1 M: several blocks
  CameraModel camera(scene.camera, 120, 90);
  const auto offsets = test::grid_offsets(2);
  const Rasterizer all(scene, camera, {}, 16);
  const FrameFragments parallel = test::rasterize_frame(all, camera, offsets);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const Rasterizer single(scene, camera, {}, 16);
  EXPECT_EQ(all.triangle_count(), single.triangle_count());
  expect_same(parallel, test::rasterize_frame(single, camera, offsets));
}

TEST(MeshSetup, DegenerateAndEdgeOnTrianglesMakeNoFragments) {
  Scene plain = test::make_scene(64, 48);
  const Mesh box = test::box({-40, -40, -40}, {40, 40, 40});
  test::add_mesh(plain, box);
  Scene extra = test::make_scene(64, 48);
  Mesh more = box;
  const uint32_t n = static_cast<uint32_t>(more.positions.size());
  // A repeated corner, three collinear points, and a triangle in a plane through the eye
  // (0, -600, 0), seen edge-on; all cross the image.
  more.positions.insert(
      more.positions.end(),
      {{-50, -60, -30}, {0, -60, 0}, {50, -60, 30}, {0, -100, -50}, {0, 100, -50}, {0, 0, 50}});
  more.triangles.insert(more.triangles.begin() + 3,
                        {{0, 7, 7}, {n, n + 1, n + 2}, {n + 3, n + 4, n + 5}});
  test::add_mesh(extra, more);
  CameraModel camera(plain.camera, 64, 48);
  const auto offsets = test::grid_offsets(3);
  expect_same(test::rasterize_frame(Rasterizer(plain, camera, {}, 16), camera, offsets),
              test::rasterize_frame(Rasterizer(extra, camera, {}, 16), camera, offsets));
}

}  // namespace
}  // namespace imx
