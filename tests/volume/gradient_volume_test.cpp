#include "volume/gradient_volume.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <variant>
#include <vector>

#include "intermix/limits.hpp"
#include "random_volumes.hpp"
#include "volume/volume_acceleration.hpp"

namespace imx {
namespace {

// Central differences are exact on a linear field, in the interior and (one-sided) at borders.
TEST(GradientVolume, IsExactOnLinearFieldsUpToQuantization) {
  VolumeData v;
  v.dims = {9, 7, 5};
  std::vector<float> f;
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 9; ++i) f.push_back(2.0f * i - 3.0f * j + 0.5f * k);
  v.voxels = std::move(f);
  GradientVolume g{AnyGrid(v)};
  for (glm::vec3 p : {glm::vec3(0), glm::vec3(4.3f, 2.7f, 1.1f), glm::vec3(8, 6, 4)}) {
    glm::vec3 d = g.sample(p);
    EXPECT_NEAR(d.x, 2.0f, 1e-3f);
    EXPECT_NEAR(d.y, -3.0f, 1e-3f);
    EXPECT_NEAR(d.z, 0.5f, 1e-3f);
  }
}

// In the interior, at voxel centres, it equals the on-the-fly gradient of the trilinear field.
TEST(GradientVolume, MatchesOnTheFlyGradientsAtVoxelCentres) {
  std::mt19937 rng(5);
  VolumeData v = test::blob_volume<int16_t>({20, 18, 16}, rng, 10.0f, -500.0f);
  AnyGrid grid(v);
  GradientVolume g(grid);
  float largest = 0.0f, worst = 0.0f;
  for (int k = 1; k < 15; ++k)
    for (int j = 1; j < 17; ++j)
      for (int i = 1; i < 19; ++i) {
        glm::vec3 p(i, j, k);
        glm::vec3 a = grid.gradient(p), b = g.sample(p);
        largest = std::max(largest, glm::length(a));
        worst = std::max(worst, glm::length(a - b));
      }
  ASSERT_GT(largest, 10.0f);
  EXPECT_LT(worst, 1e-4f * largest);
}

// Between voxel centres it is the trilinear blend of the eight voxel gradients around, up to the
// grid's far corner and on axes one voxel thick.
TEST(GradientVolume, InterpolatesTrilinearlyBetweenVoxels) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int n = 0; n < 6; ++n) {
    const glm::ivec3 all[3] = {glm::ivec3(6, 5, 4), glm::ivec3(5, 1, 3), glm::ivec3(1, 1, 4)};
    const glm::ivec3 dims = all[n % 3];
    // Both layouts: 8-bit voxels pack, an int16 volume with a step of 2000 does not.
    VolumeData v = n < 3 ? test::blob_volume<uint8_t>(dims, rng)
                         : test::blob_volume<int16_t>(dims, rng, 2.0f, -300.0f);
    if (n >= 3) {
      auto& voxels = std::get<VoxelBuffer<int16_t>>(v.voxels);
      voxels.mutable_data()[voxels.size() - 1] = 2000;
    }
    GradientVolume g{AnyGrid(v)};
    EXPECT_EQ(g.packed(), n < 3);
    auto at = [&](glm::ivec3 i) { return g.sample(glm::vec3(glm::min(i, dims - 1))); };
    for (int k = 0; k < 200; ++k) {
      glm::vec3 p = glm::vec3(unit(rng), unit(rng), unit(rng)) * glm::vec3(dims - 1);
      if (k == 0) p = glm::vec3(dims - 1);
      glm::ivec3 i0 = glm::min(glm::ivec3(p), glm::max(dims - 2, glm::ivec3(0)));
      glm::vec3 f = p - glm::vec3(i0);
      glm::vec3 expected(0.0f);
      for (int c = 0; c < 8; ++c) {
        glm::ivec3 o(c & 1, (c >> 1) & 1, (c >> 2) & 1);
        glm::vec3 w = glm::mix(1.0f - f, f, glm::vec3(o));
        expected += w.x * w.y * w.z * at(i0 + o);
      }
      glm::vec3 got = g.sample(p);
      for (int a = 0; a < 3; ++a)
        ASSERT_NEAR(got[a], expected[a], 1e-3f * (1.0f + std::abs(expected[a])))
            << "dims " << dims.x << "x" << dims.y << "x" << dims.z << " axis " << a;
    }
  }
}

// Integer voxels whose central differences fit in 10 bits are stored exactly, 4 bytes a voxel:
// every voxel-centre gradient equals the central difference with no rounding at all.
TEST(GradientVolume, PacksSmallIntegerDifferencesExactly) {
  std::mt19937 rng(17);
  VolumeData bytes = test::blob_volume<uint8_t>({13, 11, 9}, rng);
  VolumeData narrow = test::blob_volume<int16_t>({13, 11, 9}, rng, 1.0f, -100.0f);
  VolumeData floats = test::blob_volume<float>({13, 11, 9}, rng, 0.01f);
  for (const VolumeData* v : {&bytes, &narrow}) {
    AnyGrid grid(*v);
    GradientVolume g(grid);
    ASSERT_TRUE(g.packed());
    EXPECT_EQ(g.bytes(), 4u * 13 * 11 * 9);
    grid.visit([&](const auto& voxels) {
      for (int k = 0; k < 9; ++k)
        for (int j = 0; j < 11; ++j)
          for (int i = 0; i < 13; ++i) {
            glm::ivec3 p(i, j, k);
            glm::vec3 got = g.sample(glm::vec3(p));
            for (int a = 0; a < 3; ++a) {
              glm::ivec3 lo = p, hi = p;
              lo[a] = std::max(p[a] - 1, 0);
              hi[a] = std::min(p[a] + 1, voxels.dims[a] - 1);
              float want = (static_cast<float>(voxels.at(hi.x, hi.y, hi.z)) -
                            static_cast<float>(voxels.at(lo.x, lo.y, lo.z))) /
                           static_cast<float>(hi[a] - lo[a]);
              ASSERT_EQ(got[a], want) << i << " " << j << " " << k << " axis " << a;
            }
          }
    });
  }
  EXPECT_FALSE(GradientVolume(AnyGrid(floats)).packed());  // float differences need not be
                                                           // integers
}

// `auto` precomputes gradients while their copy (4 bytes a voxel for 8-bit voxels, always
// packed; 6 for others) takes at most 200 MiB plus a quarter of the voxels, and a quarter of the
// memory budget. The shape alone decides: no voxel is read or allocated.
// The central difference of voxel p along `axis` by its definition, one voxel at a time: one-sided
// at the borders, and beside no data (NaN or inf) one-sided against the voxel itself, 0 where
// that is not possible either (the voxel is no data, or both neighbours are).
float defined_difference(const VoxelGrid<float>& g, glm::ivec3 p, int axis) {
  glm::ivec3 lo = p, hi = p;
  lo[axis] = std::max(p[axis] - 1, 0);
  hi[axis] = std::min(p[axis] + 1, g.dims[axis] - 1);
  auto at = [&](glm::ivec3 q) { return g.at(q.x, q.y, q.z); };
  if (hi[axis] == lo[axis]) return 0.0f;
  float d = (at(hi) - at(lo)) / static_cast<float>(hi[axis] - lo[axis]);
  if (std::isfinite(d)) return d;
  if (no_data(at(p))) return 0.0f;
  if (no_data(at(hi))) hi = p;
  if (no_data(at(lo))) lo = p;
  if (hi[axis] == lo[axis]) return 0.0f;
  return (at(hi) - at(lo)) / static_cast<float>(hi[axis] - lo[axis]);
}

// The int16 layout holds every voxel's difference rounded half away from zero (std::lround) in
// units of scale(), 0 where it is not finite: on grids one and two voxels thick and with no data.
TEST(GradientVolume, StoresEachDifferenceRoundedInItsUnits) {
  std::mt19937 rng(23);
  // Whole numbers whose largest difference is 32767 (one-sided, at the first voxel of each row):
  // one unit is one value, so halved odd differences fall exactly between two units, either sign.
  auto ties = [&](glm::ivec3 dims) {
    std::uniform_int_distribution<int> u(-100, 100);
    std::vector<float> f(static_cast<size_t>(dims.x) * dims.y * dims.z);
    for (float& x : f) x = static_cast<float>(u(rng));
    for (size_t row = 0; row < f.size(); row += dims.x) f[row + 1] = f[row] + 32767.0f;
    VolumeData v;
    v.dims = dims;
    v.voxels = std::move(f);
    return v;
  };
  for (glm::ivec3 dims : {glm::ivec3(9, 7, 6), glm::ivec3(1, 4, 3), glm::ivec3(2, 1, 5)}) {
    for (int kind = 0; kind < 3; ++kind) {
      const bool holes = kind == 1;
      VolumeData v =
          kind == 2 && dims.x > 2 ? ties(dims) : test::blob_volume<float>(dims, rng, 3.7f, -200.0f);
      if (holes) test::punch_no_data(v, rng, -200.0f + 20.0f * 3.7f);
      const auto& voxels = std::get<VoxelBuffer<float>>(v.voxels);
      const VoxelGrid<float> grid{voxels.data(), dims};
      const GradientVolume g{AnyGrid(v)};
      ASSERT_FALSE(g.packed());
      float largest = 0.0f;
      for (int n = 0; n < dims.x * dims.y * dims.z; ++n)
        for (int a = 0; a < 3; ++a) {
          const glm::ivec3 p(n % dims.x, n / dims.x % dims.y, n / (dims.x * dims.y));
          const float d = defined_difference(grid, p, a);
          if (std::isfinite(d)) largest = std::max(largest, std::abs(d));
        }
      ASSERT_EQ(g.scale(), largest > 0.0f ? largest / 32767.0f : 1.0f);
      const float inv = 1.0f / g.scale();
      for (int n = 0; n < dims.x * dims.y * dims.z; ++n)
        for (int a = 0; a < 3; ++a) {
          const glm::ivec3 p(n % dims.x, n / dims.x % dims.y, n / (dims.x * dims.y));
          const float d = defined_difference(grid, p, a);
          const int16_t want = std::isfinite(d) ? static_cast<int16_t>(std::lround(d * inv)) : 0;
          ASSERT_EQ(g.data()[3 * n + a], want)
              << "voxel " << n << " axis " << a << " holes " << holes << " dims " << dims.x << "x"
              << dims.y << "x" << dims.z;
        }
    }
  }
}

TEST(GradientVolume, AutomaticPrecomputesWhileTheCopyKeepsMemoryNearTheVoxels) {
  auto volume = [](glm::ivec3 dims, auto element) {
    VolumeData v;
    v.dims = dims;
    v.voxels = VoxelBuffer<decltype(element)>();
    return v;
  };
  // int16: 6 V <= 200 MiB + 2 V / 4 up to 512 x 512 x 145; 8-bit: 4 V <= 200 MiB + V / 4 up to
  // 512 x 512 x 213.
  const VolumeData ct = volume({512, 512, 145}, int16_t{}),
                   big_ct = volume({512, 512, 146}, int16_t{});
  const VolumeData mr = volume({512, 512, 213}, uint8_t{}),
                   big_mr = volume({512, 512, 214}, uint8_t{});
  EXPECT_EQ(GradientVolume::bytes_at_most(mr), 4ull * 512 * 512 * 213);
  EXPECT_EQ(GradientVolume::bytes_at_most(ct), 6ull * 512 * 512 * 145);
  EXPECT_TRUE(precomputes_gradients(GradientSource::automatic, ct));
  EXPECT_TRUE(precomputes_gradients(GradientSource::automatic, mr));
  EXPECT_FALSE(precomputes_gradients(GradientSource::automatic, big_ct));
  EXPECT_FALSE(precomputes_gradients(GradientSource::automatic, big_mr));
  EXPECT_TRUE(precomputes_gradients(GradientSource::precomputed, big_ct));
  EXPECT_FALSE(precomputes_gradients(GradientSource::on_the_fly, mr));
  // A budget of 800 MiB leaves the CT's 217.5 MiB copy out, not a 64 MiB one.
  const InputLimits before = input_limits();
  set_input_limits({uint64_t{800} << 20, false});
  EXPECT_FALSE(precomputes_gradients(GradientSource::automatic, ct));
  EXPECT_TRUE(precomputes_gradients(GradientSource::automatic, volume({256, 256, 256}, uint8_t{})));
  set_input_limits(before);
}

// The listed structures are the ones built, with their sizes.
TEST(GradientVolume, ResidentPartsListWhatAccelerateBuilt) {
  auto data = std::make_shared<VolumeData>();
  data->dims = {20, 16, 12};
  std::vector<uint8_t> voxels(20 * 16 * 12);
  for (size_t n = 0; n < voxels.size(); ++n) voxels[n] = static_cast<uint8_t>(n * 7);
  data->voxels = std::move(voxels);
  VolumeObject v;
  v.data = data;
  v.shading.enabled = true;
  v.transfer_function.points = {{0.0, glm::vec4(0.0f)}, {255.0, glm::vec4(1.0f)}};
  const TfLut lut(v.transfer_function);
  for (GradientSource source : {GradientSource::automatic, GradientSource::on_the_fly}) {
    const MarchSettings settings{SkipMode::distance, Classification::preintegrated, source, 8};
    const VolumeAcceleration a = accelerate(v, lut, 1.0f, settings);
    const std::vector<ResidentPart> parts = resident_parts(v, a);
    auto bytes = [&](const std::string& name) {
      for (const ResidentPart& p : parts)
        if (p.name == name) return p.bytes;
      ADD_FAILURE() << "no part named " << name;
      return uint64_t{0};
    };
    EXPECT_EQ(bytes("voxels"), 20u * 16 * 12);
    EXPECT_EQ(bytes("gradients"), source == GradientSource::automatic ? 4u * 20 * 16 * 12 : 0u);
    EXPECT_EQ(bytes("brick ranges"), a.ranges->ranges().size() * sizeof(glm::vec2));
    EXPECT_GT(bytes("brick occupancy"), 0u);
    EXPECT_GT(bytes("pre-integration table"), 0u);
  }
}

}  // namespace
}  // namespace imx
