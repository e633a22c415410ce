// The viewer's moving frames at a level of detail: a large volume whose voxels are smaller than
// the frame's pixels is drawn from a coarser copy, placed where the volume is; small volumes,
// label maps and frames with fine pixels are left whole.
#include "server/moving_levels.hpp"

#include <cstdint>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "intermix/metrics.hpp"
#include "intermix/render.hpp"

namespace imx::server {
namespace {

// A 256³ uint8 volume (2^24 voxels, the threshold) of 1 mm voxels: a ball of 200 in 0.
std::shared_ptr<const VolumeData> ball() {
  auto v = std::make_shared<VolumeData>();
  v->dims = glm::ivec3(256);
  std::vector<uint8_t> voxels(size_t{256} * 256 * 256, 0);
  for (int k = 0; k < 256; ++k)
    for (int j = 0; j < 256; ++j)
      for (int i = 0; i < 256; ++i)
        if (glm::length(glm::dvec3(i, j, k) - glm::dvec3(127.5)) < 90.0)
          voxels[(size_t(k) * 256 + j) * 256 + i] = 200;
  v->voxels = VoxelBuffer<uint8_t>(std::move(voxels));
  v->index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-127.5));
  return v;
}

Scene scene_of(const std::shared_ptr<const VolumeData>& data, int height, double ortho_height) {
  Scene s;
  VolumeObject v;
  v.name = "ball";
  v.data = data;
  // An object transform: the level keeps it.
  const glm::dmat4 transform = glm::rotate(glm::dmat4(1.0), 0.4, glm::dvec3(0, 0, 1));
  v.index_to_world = transform * data->index_to_world;
  v.source_dims = data->dims;
  v.transfer_function.points = {
      {0.0, {0, 0, 0, 0}}, {100.0, {1, 1, 1, 0.0}}, {200.0, {1, 0.8f, 0.6f, 1.0}}};
  s.volumes.push_back(v);
  s.order.push_back({ObjectKind::volume, 0});
  s.camera.projection = Projection::orthographic;
  s.camera.ortho_height = ortho_height;
  s.camera.eye = glm::dvec3(0, -500, 0);
  s.image.width = s.image.height = height;
  return s;
}

TEST(MovingLevels, ALargeVolumeMovesAtTheLevelItsPixelsShow) {
  const auto data = ball();
  MovingLevels levels;
  // 320 mm over 40 rows: 8 mm pixels, level 3 (8 mm voxels).
  Scene moving = scene_of(data, 40, 320.0);
  const glm::dmat4 transform =
      moving.volumes[0].index_to_world * glm::inverse(data->index_to_world);
  EXPECT_EQ(levels.apply(moving), 3);
  const VolumeObject& v = moving.volumes[0];
  ASSERT_EQ(v.data->dims, glm::ivec3(32));
  EXPECT_EQ(v.source_dims, glm::ivec3(32));
  // Coarse voxel 0's centre: fine index 3.5 on every axis, through the object's transform.
  const glm::dvec3 want(transform * data->index_to_world * glm::dvec4(3.5, 3.5, 3.5, 1.0));
  EXPECT_NEAR(glm::length(glm::dvec3(v.index_to_world * glm::dvec4(0, 0, 0, 1)) - want), 0, 1e-9);
  // Made once: the next frame finds the same copy.
  Scene again = scene_of(data, 40, 320.0);
  levels.apply(again);
  EXPECT_EQ(again.volumes[0].data, v.data);

  // The level's frame is near the full-resolution one at that size.
  RenderOptions o;
  o.method = "mdvr";
  const double db = psnr(render(scene_of(data, 40, 320.0), o), render(moving, o));
  EXPECT_GE(db, 25.0);

  // 1 mm pixels: no level fits.
  Scene fine = scene_of(data, 320, 320.0);
  EXPECT_EQ(levels.apply(fine), 0);
  EXPECT_EQ(fine.volumes[0].data, data);
  // Label maps are not averaged.
  Scene labels = scene_of(data, 40, 320.0);
  labels.volumes[0].labels = std::make_shared<LabelMap>();
  EXPECT_EQ(levels.apply(labels), 0);
}

TEST(MovingLevels, SmallVolumesStayWhole) {
  auto small = std::make_shared<VolumeData>();
  small->dims = glm::ivec3(64);
  small->voxels = VoxelBuffer<uint8_t>(std::vector<uint8_t>(64 * 64 * 64, 7));
  MovingLevels levels;
  Scene s = scene_of(small, 8, 320.0);
  EXPECT_EQ(levels.apply(s), 0);
  EXPECT_EQ(s.volumes[0].data, small);
}

}  // namespace
}  // namespace imx::server
