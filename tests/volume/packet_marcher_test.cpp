#include "volume/packet_marcher.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "each_simd_target.hpp"
#include "intermix/labels.hpp"
#include "random_volumes.hpp"
#include "volume/volume_marcher.hpp"

namespace imx {
namespace {

using test::prepared;
using test::random_ray;

// Rays through the volume; about half start and end inside it (mid-brick, off the step grid).
std::vector<PacketRay> random_rays(std::mt19937& rng, const PreparedVolume& v, int count,
                                   glm::vec3 centre, float radius) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<PacketRay> rays;
  for (int k = 0; k < count; ++k) {
    Ray ray = random_ray(rng, centre, radius);
    RayInterval span = v.intersect(ray);
    if (!span.empty() && u(rng) < 0.5f) {
      float len = span.t1 - span.t0;
      span.t0 += 0.4f * u(rng) * len;
      span.t1 -= 0.4f * u(rng) * len;
    }
    rays.push_back({ray, span.t0, span.t1});
  }
  return rays;
}

// The packets, on every SIMD target, against one VolumeMarcher per ray; returns how many rays
// reached `ert`. Every ray agrees to 1e-4, but for 1 ray in 100 at most, which may differ by up
// to 1e-2: two-sided shading turns the normal toward the eye, so a light other than the
// headlight lights a piece or not as n.e crosses 0, and the two paths (or two compilers) can
// round that sign apart. In a label volume such a ray may differ in opacity too: a bisection
// step that rounds the other way moves a label boundary by 1/64 of a step (clang's baseline
// build, one ray in 203).
int expect_same_as_marcher(const PreparedVolume& v, const std::vector<PacketRay>& rays, float step,
                           std::span<const ShadingLight> lights, float ert,
                           SlabExtent extent = SlabExtent::grid) {
  std::vector<glm::vec4> want(rays.size());
  int terminated = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    glm::vec4 acc(0.0f);
    VolumeMarcher m(v, rays[i].ray, rays[i].t0, rays[i].t1, step, lights, extent);
    m.composite(acc, ert);
    terminated += acc.a >= ert;
    want[i] = acc;
  }
  test::for_each_simd_target([&](const std::string&) {
    std::vector<glm::vec4> out(rays.size(), glm::vec4(-1.0f));
    composite_packets(v, rays, step, lights, ert, out, extent);
    size_t apart = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      const glm::vec4& acc = want[i];
      float worst = 0.0f;
      for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(out[i][c] - acc[c]));
      if (worst <= 1e-4f) continue;
      ++apart;
      EXPECT_LE(worst, 1e-2f) << "ray " << i;
      if (!v.labels.active()) {
        EXPECT_NEAR(out[i].a, acc.a, 1e-4f) << "ray " << i;  // the jump is in the colour only
      }
    }
    EXPECT_LE(apart, rays.size() / 100);
  });
  return terminated;
}

const ShadingLight kLights[2] = {
    ShadingLight{},
    {false, glm::normalize(glm::vec3(0.3f, -0.8f, 0.5f)), glm::vec3(0.8f, 0.7f, 0.6f)}};

// `no_data`: float voxels of the background and a few others made NaN or inf.
template <class T>
void check_voxel_type(float scale, float offset, uint32_t seed, bool no_data = false) {
  std::mt19937 rng(seed);
  int terminated = 0, marched = 0;
  for (int trial = 0; trial < 6; ++trial) {
    VolumeObject obj;
    obj.name = "blobs";
    glm::ivec3 dims = trial == 5 ? glm::ivec3(2, 3, 2) : glm::ivec3(29, 23, 26);
    auto data = std::make_shared<VolumeData>(test::blob_volume<T>(dims, rng, scale, offset));
    if (no_data) test::punch_no_data(*data, rng, offset + 20.0f * scale);
    obj.data = data;
    obj.index_to_world = glm::dmat4(glm::dmat3(0.9, 0.1, 0.0, -0.1, 1.1, 0.0, 0.0, 0.2, 1.3));
    obj.transfer_function = test::random_tf(rng, offset, offset + 255.0f * scale);
    obj.shading = {trial != 2, 0.2f, 0.7f, 0.3f, trial == 3 ? 7.0f : 32.0f};
    MarchSettings settings{
        trial % 3 == 0 ? SkipMode::distance : (trial % 3 == 1 ? SkipMode::bricks : SkipMode::none),
        Classification::preintegrated,
        trial % 2 ? GradientSource::on_the_fly : GradientSource::precomputed, 4};
    const float step = trial == 4 ? 0.37f : 0.8f;
    PreparedVolume v = prepared(obj, step, settings);
    EXPECT_EQ(v.has_no_data, no_data);
    std::span<const ShadingLight> lights(kLights, trial == 1 ? 1 : 2);
    EXPECT_TRUE(packet_marching_supported(v, lights));
    glm::vec3 centre = glm::vec3(dims) * 0.5f;
    std::vector<PacketRay> rays = random_rays(rng, v, 203, centre, 1.5f * dims.x);
    for (float ert : {0.3f, 0.99f, 1.0f}) {
      terminated += expect_same_as_marcher(v, rays, step, lights, ert);
      marched += static_cast<int>(rays.size());
    }
    // As the slab methods march: each piece shaded where its light comes from, at one point or
    // two (a mistake in the lanes' centre or spread moves the shading point and fails this).
    terminated += expect_same_as_marcher(v, rays, step, lights, 0.99f, SlabExtent::visible);
    marched += static_cast<int>(rays.size());
  }
  EXPECT_GT(terminated, marched / 40);  // early termination was exercised
}

TEST(PacketMarcher, MatchesVolumeMarcherU8) {
  check_voxel_type<uint8_t>(1.0f, 0.0f, 11);
}
TEST(PacketMarcher, MatchesVolumeMarcherI16) {
  check_voxel_type<int16_t>(8.0f, -1000.0f, 12);
}
TEST(PacketMarcher, MatchesVolumeMarcherU16) {
  check_voxel_type<uint16_t>(200.0f, 0.0f, 13);
}
TEST(PacketMarcher, MatchesVolumeMarcherFloat) {
  check_voxel_type<float>(0.01f, -0.5f, 14);
}
TEST(PacketMarcher, MatchesVolumeMarcherWithNoData) {
  check_voxel_type<float>(0.01f, -0.5f, 15, true);
}

// The slab methods' march (march_slab_packets) on every SIMD target against VolumeMarcher's
// visible pieces, ray by ray: the same pieces, each trimmed to its light, until the ray's
// composite reaches ERT. As for composites, 1 ray in 100 may differ in a colour by up to 1e-2.
TEST(PacketMarcher, MarchesTheMarchersSlabs) {
  std::mt19937 rng(17);
  VolumeObject obj;
  obj.name = "blobs";
  const glm::ivec3 dims(29, 23, 26);
  obj.data = std::make_shared<VolumeData>(test::blob_volume<int16_t>(dims, rng, 8.0f, -1000.0f));
  obj.transfer_function = test::random_tf(rng, -1000.0f, -1000.0f + 255.0f * 8.0f);
  obj.shading = {true, 0.2f, 0.7f, 0.3f, 32.0f};
  const float step = 0.8f, ert = 0.99f;
  const PreparedVolume v =
      prepared(obj, step,
               {SkipMode::distance, Classification::preintegrated, GradientSource::precomputed, 4});
  ASSERT_TRUE(packet_marching_supported(v, kLights));
  const std::vector<PacketRay> rays = random_rays(rng, v, 203, glm::vec3(dims) * 0.5f, 45.0f);
  std::vector<std::vector<Slab>> want(rays.size());
  size_t slabs = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    VolumeMarcher m(v, rays[i].ray, rays[i].t0, rays[i].t1, step, kLights, SlabExtent::visible);
    glm::vec4 acc(0.0f);
    Slab s;
    while (!(acc.a >= ert) && m.next(s)) {
      if (s.is_empty()) continue;
      want[i].push_back(s);
      acc = over(acc, s.color);
    }
    slabs += want[i].size();
  }
  EXPECT_GT(slabs, rays.size());  // most rays see several pieces
  struct Record final : SlabSink {
    std::vector<std::vector<Slab>> got;
    bool take(size_t ray, const Slab& slab) override {
      got[ray].push_back(slab);
      return true;
    }
  };
  test::for_each_simd_target([&](const std::string&) {
    Record sink;
    sink.got.resize(rays.size());
    march_slab_packets(v, rays, step, kLights, ert, sink);
    size_t apart = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(sink.got[i].size(), want[i].size()) << "ray " << i;
      float worst = 0.0f;
      for (size_t k = 0; k < want[i].size(); ++k) {
        const Slab &a = sink.got[i][k], &b = want[i][k];
        EXPECT_NEAR(a.t_back, b.t_back, 1e-4f * (1.0f + std::abs(b.t_back))) << "ray " << i;
        EXPECT_NEAR(a.thickness, b.thickness, 1e-4f * (1.0f + b.thickness)) << "ray " << i;
        for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(a.color[c] - b.color[c]));
      }
      if (worst <= 1e-4f) continue;
      ++apart;
      EXPECT_LE(worst, 1e-2f) << "ray " << i;
    }
    EXPECT_LE(apart, rays.size() / 100);
  });
}

// Label maps (style "labels") in lanes: the blobs cut into labels, a table with opaque,
// faint and hidden labels and unlisted ones in the default palette, smooth and nearest
// classification, each voxel type (float labels as whole numbers, int16 ones negative too).
template <class T>
void check_label_type(float scale, float offset, uint32_t seed) {
  std::mt19937 rng(seed);
  int terminated = 0, marched = 0;
  for (int trial = 0; trial < 4; ++trial) {
    VolumeObject obj;
    obj.name = "labels";
    const glm::ivec3 dims = trial == 3 ? glm::ivec3(3, 4, 2) : glm::ivec3(27, 22, 25);
    VolumeData blobs = test::blob_volume<T>(dims, rng);
    T* v = std::get<VoxelBuffer<T>>(blobs.voxels).mutable_data();
    for (size_t n = 0; n < blobs.voxel_count(); ++n)  // labels 0 .. 5, then scaled and moved
      v[n] = static_cast<T>(std::floor(static_cast<float>(v[n]) / 45.0f) * scale + offset);
    obj.data = std::make_shared<VolumeData>(std::move(blobs));
    auto map = std::make_shared<LabelMap>();
    auto label = [&](int k) {
      return static_cast<int32_t>(static_cast<float>(k) * scale + offset);
    };
    map->entries = {{label(1), "faint", {0.2f, 0.4f, 0.9f}, 0.05f, true},
                    {label(2), "opaque", {0.9f, 0.3f, 0.3f}, 1.0f, true},
                    {label(3), "hidden", {0.1f, 0.9f, 0.1f}, 0.7f, false},
                    {label(4), "half", {0.9f, 0.9f, 0.8f}, 0.5f, true}};
    map->interpolation = trial == 1 ? LabelInterpolation::nearest : LabelInterpolation::smooth;
    map->unit_distance = 0.7;
    obj.labels = map;
    obj.shading = {trial != 2, 0.2f, 0.7f, 0.3f, 24.0f};
    MarchSettings settings{trial == 0 ? SkipMode::bricks : SkipMode::distance,
                           Classification::preintegrated, GradientSource::precomputed, 4};
    const float step = trial == 2 ? 0.43f : 0.8f;
    PreparedVolume pv = prepared(obj, step, settings);
    ASSERT_TRUE(pv.labels.active());
    std::span<const ShadingLight> lights(kLights, 2);
    EXPECT_TRUE(packet_marching_supported(pv, lights));
    std::vector<PacketRay> rays =
        random_rays(rng, pv, 203, glm::vec3(dims) * 0.5f, 1.5f * static_cast<float>(dims.x));
    for (float ert : {0.3f, 0.99f, 1.0f}) {
      terminated += expect_same_as_marcher(pv, rays, step, lights, ert);
      marched += static_cast<int>(rays.size());
    }
  }
  EXPECT_GT(terminated, marched / 40);
}

TEST(PacketMarcher, MatchesVolumeMarcherOnLabelsU8) {
  check_label_type<uint8_t>(1.0f, 0.0f, 21);
}
TEST(PacketMarcher, MatchesVolumeMarcherOnLabelsI16) {
  check_label_type<int16_t>(300.0f, -700.0f, 22);
}
TEST(PacketMarcher, MatchesVolumeMarcherOnLabelsU16) {
  check_label_type<uint16_t>(1000.0f, 7.0f, 23);
}
TEST(PacketMarcher, MatchesVolumeMarcherOnLabelsFloat) {
  check_label_type<float>(1.0f, 2.0f, 24);
}

// A TF with no opacity anywhere: every brick is empty and every ray stays transparent.
TEST(PacketMarcher, EmptyTransferFunctionGivesNothing) {
  std::mt19937 rng(5);
  VolumeObject obj;
  obj.name = "blobs";
  obj.data = std::make_shared<VolumeData>(test::blob_volume<uint8_t>({20, 20, 20}, rng));
  obj.transfer_function.points = {{0.0, glm::vec4(1, 1, 1, 0)}, {255.0, glm::vec4(1, 0, 0, 0)}};
  obj.shading.enabled = true;
  const float step = 1.0f;
  PreparedVolume v = prepared(obj, step, {SkipMode::distance, Classification::preintegrated});
  std::vector<PacketRay> rays = random_rays(rng, v, 40, glm::vec3(10.0f), 30.0f);
  test::for_each_simd_target([&](const std::string&) {
    std::vector<glm::vec4> out(rays.size(), glm::vec4(-1.0f));
    composite_packets(v, rays, step, kLights, 0.99f, out);
    for (const glm::vec4& c : out) EXPECT_EQ(c, glm::vec4(0.0f));
  });
}

// Rays along the grid axes and the diagonals of its planes, started on brick boundaries: the
// lane brick walk must handle axes a ray never crosses, starts on a boundary and crossings of two
// boundaries at once, in both skip modes, as BrickDda does.
TEST(PacketMarcher, WalksBricksAlongAxesAsTheMarcherDoes) {
  std::mt19937 rng(21);
  VolumeObject obj;
  obj.name = "blobs";
  obj.data = std::make_shared<VolumeData>(test::blob_volume<uint8_t>({33, 33, 33}, rng));
  obj.transfer_function.points = {{0.0, glm::vec4(1, 1, 1, 0)},
                                  {120.0, glm::vec4(1, 1, 1, 0)},
                                  {200.0, glm::vec4(1, 0.5, 0.2, 0.6)},
                                  {255.0, glm::vec4(1, 0.5, 0.2, 0.9)}};
  obj.shading = {true, 0.2f, 0.7f, 0.3f, 32.0f};
  const float step = 1.0f;
  std::vector<PacketRay> rays;
  const glm::vec3 dirs[] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},  {0, -1, 0}, {0, 0, 1},
                            {0, 0, -1}, {1, 1, 0},  {-1, 0, 1}, {0, -1, -1}};
  for (glm::vec3 d : dirs) {
    d = glm::normalize(d);
    for (float u : {4.0f, 8.0f, 13.5f, 16.0f, 24.0f})
      for (float w : {8.0f, 11.0f, 16.0f, 20.0f}) {
        // A start point on the plane through the middle of the grid, moved back along the ray.
        glm::vec3 p(16.0f);
        int a = d.x != 0.0f ? 0 : (d.y != 0.0f ? 1 : 2);
        p[(a + 1) % 3] = u, p[(a + 2) % 3] = w;
        rays.push_back({Ray{p - 40.0f * d, d}, 0.0f, 0.0f});
      }
  }
  for (SkipMode mode : {SkipMode::distance, SkipMode::bricks}) {
    int with_work = 0;
    PreparedVolume v =
        prepared(obj, step, {mode, Classification::preintegrated, GradientSource::precomputed, 4});
    for (PacketRay& r : rays) {
      RayInterval span = v.intersect(r.ray);
      r.t0 = span.t0, r.t1 = span.t1;
      with_work += !span.empty();
    }
    EXPECT_GT(with_work, static_cast<int>(rays.size()) / 2);  // most rays cross the grid
    for (float ert : {0.5f, 0.99f}) expect_same_as_marcher(v, rays, step, kLights, ert);
  }
}

// Small visible cores far apart in a large empty grid: distance skipping jumps many bricks at a
// time, and each jump must land in the brick BrickDda lands in on every axis.
TEST(PacketMarcher, JumpsOverWideEmptySpaceAsTheMarcherDoes) {
  std::mt19937 rng(33);
  VolumeObject obj;
  obj.name = "cores";
  obj.data = std::make_shared<VolumeData>(test::blob_volume<uint8_t>({64, 64, 64}, rng, 1, 0, 6));
  obj.index_to_world = glm::dmat4(glm::dmat3(1.0, 0.2, 0.0, -0.1, 0.9, 0.1, 0.0, 0.0, 1.1));
  obj.transfer_function.points = {{0.0, glm::vec4(1, 1, 1, 0)},
                                  {160.0, glm::vec4(1, 1, 1, 0)},
                                  {255.0, glm::vec4(0.3, 0.6, 1, 0.8)}};
  obj.shading = {true, 0.2f, 0.7f, 0.3f, 32.0f};
  const float step = 0.7f;
  PreparedVolume v =
      prepared(obj, step,
               {SkipMode::distance, Classification::preintegrated, GradientSource::precomputed, 4});
  std::vector<PacketRay> rays = random_rays(rng, v, 400, glm::vec3(32.0f), 90.0f);
  test::for_each_simd_target([&](const std::string&) {
    int seen = 0;
    std::vector<glm::vec4> out(rays.size());
    composite_packets(v, rays, step, kLights, 0.99f, out);
    for (const glm::vec4& c : out) seen += c.a > 0.01f;
    EXPECT_GT(seen, 20);  // enough rays reach a core
  });
  expect_same_as_marcher(v, rays, step, kLights, 0.99f);
}

// The box and clip-plane test in lanes against PreparedVolume::intersect: rays that miss, rays
// parallel to a grid axis or a plane, and a batch that is not a multiple of eight.
TEST(PacketMarcher, IntersectsAsThePreparedVolumeDoes) {
  std::mt19937 rng(51);
  VolumeObject obj;
  obj.name = "blobs";
  obj.data = std::make_shared<VolumeData>(test::blob_volume<uint8_t>({30, 25, 20}, rng));
  obj.index_to_world = glm::dmat4(glm::dmat3(1.0, 0.0, 0.0, 0.0, 1.2, 0.0, 0.0, 0.0, 0.8));
  obj.clip_planes = {{glm::dvec3(15, 15, 8), glm::normalize(glm::dvec3(0.3, -1.0, 0.2))},
                     {glm::dvec3(0, 0, 12), glm::dvec3(0, 0, -1)}};
  obj.transfer_function = test::random_tf(rng, 0.0f, 255.0f);
  PreparedVolume v = prepared(obj, 1.0f, {SkipMode::distance, Classification::preintegrated});
  std::vector<PacketRay> rays = random_rays(rng, v, 203, glm::vec3(15.0f, 15.0f, 8.0f), 40.0f);
  for (int k = 0; k < 12; ++k) {  // along x (parallel to y, z and the second plane), in and out
    const float y = k < 6 ? 10.0f + k : -5.0f - k;
    rays[static_cast<size_t>(k)].ray = Ray{glm::vec3(-20.0f, y, 5.0f + k), glm::vec3(1, 0, 0)};
  }
  int hits = 0;
  intersect_packets(v, rays);
  for (size_t i = 0; i < rays.size(); ++i) {
    RayInterval want = v.intersect(rays[i].ray);
    const bool got_empty = RayInterval{rays[i].t0, rays[i].t1}.empty();
    ASSERT_EQ(want.empty(), got_empty) << "ray " << i;
    if (want.empty()) continue;
    ++hits;
    EXPECT_NEAR(rays[i].t0, want.t0, 1e-4f * (1.0f + std::abs(want.t0))) << "ray " << i;
    EXPECT_NEAR(rays[i].t1, want.t1, 1e-4f * (1.0f + std::abs(want.t1))) << "ray " << i;
  }
  EXPECT_GT(hits, 40);
  EXPECT_LT(hits, static_cast<int>(rays.size()) - 40);
}

// Both projections, a wide image and a tall one, blocks anywhere in the image.
TEST(PacketCamera, GivesTheCameraModelsRays) {
  Camera cam;
  cam.eye = {40.0, -300.0, 120.0};
  cam.target = {5.0, 10.0, -20.0};
  cam.up = {0.1, 0.0, 1.0};
  for (Projection projection : {Projection::perspective, Projection::orthographic}) {
    cam.projection = projection;
    for (glm::ivec2 size : {glm::ivec2(96, 40), glm::ivec2(33, 120)}) {
      const CameraModel model(cam, size.x, size.y);
      const PacketCamera lanes(model);
      for (glm::ivec2 at :
           {glm::ivec2(0, 0), glm::ivec2(12, 6), glm::ivec2(size.x - 4, size.y - 2)}) {
        PacketRay block[8];
        lanes.block(at.x, at.y, block);
        for (int k = 0; k < 8; ++k) {
          const Ray want = model.ray(at.x + k % 4 + 0.5, at.y + k / 4 + 0.5);
          for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(block[k].ray.dir[a], want.dir[a], 1e-6f) << "lane " << k;
            EXPECT_NEAR(block[k].ray.origin[a], want.origin[a], 1e-4f) << "lane " << k;
          }
        }
      }
    }
  }
}

// A fractional shininess runs in lanes (the same specular table); what the lanes do not handle
// (post-classification, a shininess below 1, which has no table) goes to VolumeMarcher: the
// same answers either way.
TEST(PacketMarcher, FallsBackOnlyWhereLanesDoNotApply) {
  std::mt19937 rng(9);
  VolumeObject obj;
  obj.name = "blobs";
  obj.data = std::make_shared<VolumeData>(test::blob_volume<int16_t>({24, 20, 22}, rng));
  obj.transfer_function = test::random_tf(rng, 0.0f, 255.0f);
  obj.shading = {true, 0.2f, 0.7f, 0.3f, 12.5f};
  const float step = 0.9f;
  PreparedVolume frac = prepared(obj, step, {SkipMode::distance, Classification::preintegrated});
  PreparedVolume post = prepared(obj, step, {SkipMode::distance, Classification::post});
  obj.shading.shininess = 0.5f;
  PreparedVolume dull = prepared(obj, step, {SkipMode::distance, Classification::preintegrated});
  EXPECT_TRUE(packet_marching_supported(frac, kLights));
  EXPECT_FALSE(packet_marching_supported(post, kLights));
  EXPECT_FALSE(packet_marching_supported(dull, kLights));
  std::vector<PacketRay> rays = random_rays(rng, frac, 30, glm::vec3(12.0f), 30.0f);
  expect_same_as_marcher(frac, rays, step, kLights, 0.99f);
  expect_same_as_marcher(post, rays, step, kLights, 0.99f);
  expect_same_as_marcher(dull, rays, step, kLights, 0.99f);
  expect_same_as_marcher(frac, {}, step, kLights, 0.99f);
}

}  // namespace
}  // namespace imx
