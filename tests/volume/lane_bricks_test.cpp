#include "volume/lane_bricks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>

#include "random_volumes.hpp"
#include "volume/brick_dda.hpp"

namespace imx {
namespace {

// What VolumeMarcher::skip_empty finds from t with BrickDda, one brick at a time: the entry and
// exit times of the first occupied brick at or after t (the exit no later than t1), or nothing
// before t1.
struct Found {
  bool any = false;
  float enter = 0.0f, leave = 0.0f;
};
// Half the bricks, by a hash of their index: what a caller's test of a brick may refuse.
bool counted(uint32_t brick) {
  return ((brick * 2654435761u) >> 7 & 1u) != 0;
}

Found walk_one_brick_at_a_time(const BrickOccupancy& occ, const Ray& ray, float t, float t1,
                               bool only_counted) {
  BrickDda dda(occ.grid(), ray.origin, ray.dir, t, t1);
  auto stops = [&](glm::ivec3 b) {
    return occ.occupied(b) &&
           (!only_counted || counted(static_cast<uint32_t>(occ.grid().index(b))));
  };
  while (!dda.done() && !stops(dda.brick())) dda.next();
  if (dda.done()) return {};
  return {true, dda.t_enter(), dda.t_exit()};
}

#if IMX_PACKET_LANES
using lanes::kLanes;
using lanes::LaneBricks;

// Rays in index space from random starts, eight at a time: both skip modes find the brick a
// plain walk finds, whether the start lies in an empty brick, an occupied one or outside the grid,
// and with a test of each brick, the first occupied one that passes it.
TEST(LaneBricks, FindTheFirstOccupiedBrickAsBrickDdaDoes) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int found_after_a_jump = 0, none = 0, checked = 0, passed_over = 0;
  for (int trial = 0; trial < 6; ++trial) {
    VolumeObject obj;
    obj.name = "blobs";
    const glm::ivec3 dims = trial % 2 ? glm::ivec3(61, 47, 53) : glm::ivec3(33, 40, 29);
    obj.data = std::make_shared<VolumeData>(test::blob_volume<uint8_t>(dims, rng, 1, 0, 5));
    obj.transfer_function = test::random_tf(rng, 0.0f, 255.0f);
    const int brick = trial < 3 ? 4 : 8;
    const PreparedVolume bricks = test::prepared(
        obj, 1.0f, {SkipMode::bricks, Classification::post, GradientSource::on_the_fly, brick});
    const PreparedVolume distance = test::prepared(
        obj, 1.0f, {SkipMode::distance, Classification::post, GradientSource::on_the_fly, brick});
    const BrickOccupancy& occ = *distance.accel.occupancy;
    for (int batch = 0; batch < 40; ++batch) {
      alignas(32) float o[3][kLanes], d[3][kLanes], t[kLanes], t1[kLanes];
      Ray rays[kLanes];
      for (int l = 0; l < kLanes; ++l) {
        rays[l] = test::random_ray(rng, glm::vec3(dims) * 0.5f, 1.2f * dims.x);
        if (l == 3) rays[l].dir = glm::normalize(glm::vec3(rays[l].dir.x, 0.0f, rays[l].dir.z));
        RayInterval span = distance.intersect(Ray{rays[l].origin, rays[l].dir});
        float len = span.empty() ? 0.0f : span.t1 - span.t0;
        t[l] = span.empty() ? 0.0f : span.t0 + (l % 2 ? u(rng) * 0.5f * len : -1.0f);
        t1[l] = span.empty() ? 1.0f : span.t1;
        for (int a = 0; a < 3; ++a) o[a][l] = rays[l].origin[a], d[a][l] = rays[l].dir[a];
      }
      const float* const origin[3] = {o[0], o[1], o[2]};
      const float* const dir[3] = {d[0], d[1], d[2]};
      for (int pass = 0; pass < 4; ++pass) {
        const PreparedVolume* v = pass % 2 ? &distance : &bricks;
        const bool only_counted = pass >= 2;
        LaneBricks walker(*v->accel.occupancy, v->accel.skip);
        alignas(32) float enter[kLanes], leave[kLanes];
        __m256 e = _mm256_set1_ps(-1.0f), x = _mm256_set1_ps(-1.0f);
        const LaneBricks::Rays r = walker.load(origin, dir);
        const __m256 from = _mm256_load_ps(t), to = _mm256_load_ps(t1);
        const auto counts = [](__m256i brick) {
          const __m256i bit = _mm256_and_si256(
              _mm256_srli_epi32(_mm256_mullo_epi32(brick, _mm256_set1_epi32(-1640531535)), 7),
              _mm256_set1_epi32(1));
          return _mm256_castsi256_ps(_mm256_cmpeq_epi32(bit, _mm256_set1_epi32(1)));
        };
        const unsigned missed = only_counted
                                    ? walker.first_occupied(r, 0xff, from, to, e, x, counts)
                                    : walker.first_occupied(r, 0xff, from, to, e, x);
        _mm256_store_ps(enter, e), _mm256_store_ps(leave, x);
        for (int l = 0; l < kLanes; ++l) {
          Found want = walk_one_brick_at_a_time(occ, rays[l], t[l], t1[l], only_counted);
          ++checked;
          EXPECT_EQ(!want.any, ((missed >> l) & 1u) != 0) << "trial " << trial << " lane " << l;
          if (!want.any) {
            none += v == &distance && !only_counted;
            continue;
          }
          const float tol = 1e-4f * (1.0f + std::abs(want.leave));
          EXPECT_NEAR(enter[l], want.enter, tol) << "trial " << trial << " lane " << l;
          EXPECT_NEAR(std::min(leave[l], t1[l]), want.leave, tol)
              << "trial " << trial << " lane " << l;
          found_after_a_jump += v == &distance && want.enter > t[l] + 2.0f * brick;
          passed_over +=
              only_counted &&
              want.enter > walk_one_brick_at_a_time(occ, rays[l], t[l], t1[l], false).enter;
        }
      }
    }
  }
  // Both outcomes and long jumps happened.
  EXPECT_GT(found_after_a_jump, checked / 50);
  EXPECT_GT(none, checked / 50);
  EXPECT_GT(passed_over, checked / 50) << "the test of bricks never walked past one";
}
#endif

}  // namespace
}  // namespace imx
