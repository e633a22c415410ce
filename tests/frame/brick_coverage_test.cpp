#include "frame/brick_coverage.hpp"

#include <gtest/gtest.h>

#include <random>

#include "../volume/random_volumes.hpp"
#include "volume/brick_dda.hpp"

namespace imx {
namespace {

// Whether the ray through pixel (x, y) meets an occupied brick, by the marcher's own walk.
bool meets_occupied_brick(const PreparedVolume& v, const CameraModel& camera, int x, int y) {
  const Ray ray = camera.ray(x + 0.5, y + 0.5);
  const RayInterval span = v.intersect(ray);
  if (span.empty()) return false;
  const BrickOccupancy& occ = *v.accel.occupancy;
  BrickDda dda(occ.grid(), v.to_index(ray.origin), glm::mat3(v.world_to_index) * ray.dir, span.t0,
               span.t1);
  for (; !dda.done(); dda.next())
    if (occ.occupied(dda.brick())) return true;
  return false;
}

// Every pixel whose ray meets an occupied brick is covered, in both projections, from random
// sides and from inside the grid; returns how many pixels whose rays meet only empty bricks are
// not covered.
int check_coverage(const VolumeObject& obj, int brick_size = 8) {
  const PreparedVolume v = test::prepared(
      obj, 1.0f,
      {SkipMode::distance, Classification::preintegrated, GradientSource::precomputed, brick_size});
  EXPECT_GT(v.accel.occupancy->occupied_count(), 0u);
  EXPECT_LT(v.accel.occupancy->occupied_count(), v.accel.occupancy->grid().count() / 2);
  Camera cam;
  cam.target = {24.0, 20.0, 25.0};
  cam.ortho_height = 90.0;
  int left_out = 0;
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  constexpr int kViews = 16;
  for (int view = 0; view < kViews; ++view) {
    // The last view from inside the grid; one in four orthographic.
    const glm::dvec3 way = glm::normalize(glm::dvec3(n(rng), n(rng), n(rng)));
    cam.eye = view == kViews - 1 ? glm::dvec3(20.0, 18.0, 20.0) : cam.target + 150.0 * way;
    cam.projection = view % 4 == 2 ? Projection::orthographic : Projection::perspective;
    const CameraModel camera(cam, 75, 61);
    const BrickCoverage coverage(v, camera);
    for (int y = 0; y < camera.height(); ++y)
      for (int x = 0; x < camera.width(); ++x) {
        if (meets_occupied_brick(v, camera, x, y)) {
          EXPECT_TRUE(coverage.covered(x, y)) << "view " << view << " pixel " << x << ", " << y;
        } else if (!coverage.covered(x, y)) {
          ++left_out;
        }
        if (view == kViews - 1) {
          EXPECT_TRUE(coverage.covered(x, y)) << "eye inside the grid";
        }
      }
  }
  return left_out;
}

VolumeObject volume_object(VolumeData data) {
  VolumeObject obj;
  obj.name = "blobs";
  obj.data = std::make_shared<VolumeData>(std::move(data));
  obj.index_to_world = glm::dmat4(glm::dmat3(1.1, 0.2, 0.0, -0.1, 0.9, 0.1, 0.0, 0.0, 1.3));
  obj.transfer_function.points = {{0.0f, glm::vec4(1.0f, 1.0f, 1.0f, 0.0f)},
                                  {70.0f, glm::vec4(1.0f, 1.0f, 1.0f, 0.0f)},
                                  {255.0f, glm::vec4(1.0f, 0.8f, 0.6f, 0.9f)}};
  return obj;
}

TEST(BrickCoverage, CoversEveryRayThatMeetsBlobs) {
  std::mt19937 rng(4);
  EXPECT_GT(
      check_coverage(volume_object(test::blob_volume<uint8_t>({48, 40, 36}, rng, 1.0f, 0.0f, 2))),
      3000);
}

VolumeData one_bright_voxel() {
  VolumeData data;
  data.dims = {48, 40, 36};
  std::vector<uint8_t> voxels(static_cast<size_t>(48) * 40 * 36, 0);
  voxels[(static_cast<size_t>(20) * 40 + 15) * 48 + 24] = 255;
  data.voxels = std::move(voxels);
  return data;
}

// One bright voxel: the few bricks around it are all that is occupied, so the coverage is tight
// and a rectangle a pixel too small, or one brick left out, shows.
TEST(BrickCoverage, CoversEveryRayThatMeetsTheBricksOfOneVoxel) {
  EXPECT_GT(check_coverage(volume_object(one_bright_voxel())), 10000);
}

// One-voxel bricks make 47 a side, which the coverage takes in cells of 2 x 2 x 2 bricks.
TEST(BrickCoverage, CoversEveryRayWhenBricksAreTakenInCells) {
  EXPECT_GT(check_coverage(volume_object(one_bright_voxel()), 1), 10000);
}

}  // namespace
}  // namespace imx
