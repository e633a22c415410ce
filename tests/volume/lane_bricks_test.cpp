// LaneBricks on every SIMD target this build compiled that the machine runs (Highway's per-target
// test pattern: this file is compiled once per target by foreach_target).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <random>
#include <string>

#include "random_volumes.hpp"
#include "volume/brick_dda.hpp"

// Compiled once, before the per-target parts.
#ifndef IMX_TESTS_LANE_BRICKS_TEST_ONCE_
#define IMX_TESTS_LANE_BRICKS_TEST_ONCE_
namespace imx::lane_bricks_test {

// What VolumeMarcher::skip_empty finds from t with BrickDda, one brick at a time: the entry and
// exit times of the first occupied brick at or after t (the exit no later than t1), or nothing
// before t1.
struct Found {
  bool any = false;
  float enter = 0.0f, leave = 0.0f;
};
// Half the bricks, by a hash of their index: what a caller's test of a brick may refuse.
inline bool counted(uint32_t brick) {
  return ((brick * 2654435761u) >> 7 & 1u) != 0;
}

inline Found walk_one_brick_at_a_time(const BrickOccupancy& occ, const Ray& ray, float t, float t1,
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

}  // namespace imx::lane_bricks_test
#endif  // IMX_TESTS_LANE_BRICKS_TEST_ONCE_

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "volume/lane_bricks_test.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "volume/lane_bricks-inl.hpp"

HWY_BEFORE_NAMESPACE();
namespace imx::HWY_NAMESPACE {
namespace {

namespace hn = hwy::HWY_NAMESPACE;
using namespace lanes;
using namespace lane_bricks_test;

// Rays in index space from random starts, kLanes at a time (the same rays on every target): both
// skip modes find the brick a plain walk finds, whether the start lies in an empty brick, an
// occupied one or outside the grid, and with a test of each brick, the first occupied one that
// passes it.
void find_first_occupied_as_brick_dda_does() {
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
    for (int batch = 0; batch < 320 / kLanes; ++batch) {
      HWY_ALIGN float o[3][kLanes], d[3][kLanes], t[kLanes], t1[kLanes];
      Ray rays[kLanes];
      for (int l = 0; l < kLanes; ++l) {
        const int i = batch * kLanes + l;  // the ray's number in the trial
        rays[l] = test::random_ray(rng, glm::vec3(dims) * 0.5f, 1.2f * dims.x);
        if (i % 8 == 3) rays[l].dir = glm::normalize(glm::vec3(rays[l].dir.x, 0.0f, rays[l].dir.z));
        RayInterval span = distance.intersect(Ray{rays[l].origin, rays[l].dir});
        float len = span.empty() ? 0.0f : span.t1 - span.t0;
        t[l] = span.empty() ? 0.0f : span.t0 + (i % 2 ? u(rng) * 0.5f * len : -1.0f);
        t1[l] = span.empty() ? 1.0f : span.t1;
        for (int a = 0; a < 3; ++a) o[a][l] = rays[l].origin[a], d[a][l] = rays[l].dir[a];
      }
      const float* const origin[3] = {o[0], o[1], o[2]};
      const float* const dir[3] = {d[0], d[1], d[2]};
      for (int pass = 0; pass < 4; ++pass) {
        const PreparedVolume* v = pass % 2 ? &distance : &bricks;
        const bool only_counted = pass >= 2;
        LaneBricks walker(*v->accel.occupancy, v->accel.skip);
        HWY_ALIGN float enter[kLanes], leave[kLanes];
        VF e = splat(-1.0f), x = splat(-1.0f);
        LaneBricks::Rays r;
        walker.rays(origin, dir, r);
        const VF from = load(t), to = load(t1);
        // counted() in lanes.
        const auto counts = [](VI brick) HWY_ATTR {
          const VU hash = hn::Mul(hn::BitCast(DU(), brick), hn::Set(DU(), 2654435761u));
          const VU bit = hn::And(hn::ShiftRight<7>(hash), hn::Set(DU(), 1u));
          return to_float(hn::RebindMask(DI(), hn::Eq(bit, hn::Set(DU(), 1u))));
        };
        const unsigned missed = only_counted
                                    ? walker.first_occupied(r, kAllLanes, from, to, e, x, counts)
                                    : walker.first_occupied(r, kAllLanes, from, to, e, x);
        store(e, enter), store(x, leave);
        for (int l = 0; l < kLanes; ++l) {
          Found want = walk_one_brick_at_a_time(occ, rays[l], t[l], t1[l], only_counted);
          ++checked;
          EXPECT_EQ(!want.any, ((missed >> l) & 1u) != 0)
              << "trial " << trial << " ray " << batch * kLanes + l;
          if (!want.any) {
            none += v == &distance && !only_counted;
            continue;
          }
          const float tol = 1e-4f * (1.0f + std::abs(want.leave));
          EXPECT_NEAR(enter[l], want.enter, tol)
              << "trial " << trial << " ray " << batch * kLanes + l;
          EXPECT_NEAR(std::min(leave[l], t1[l]), want.leave, tol)
              << "trial " << trial << " ray " << batch * kLanes + l;
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

}  // namespace

// The test's entry on this target.
void check_lane_bricks() {
  find_first_occupied_as_brick_dda_does();
}

}  // namespace imx::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "each_simd_target.hpp"

namespace imx {
namespace {

HWY_EXPORT(check_lane_bricks);

TEST(LaneBricks, FindTheFirstOccupiedBrickAsBrickDdaDoes) {
  test::for_each_simd_target([](const std::string&) { HWY_DYNAMIC_DISPATCH(check_lane_bricks)(); });
}

}  // namespace
}  // namespace imx
#endif  // HWY_ONCE
