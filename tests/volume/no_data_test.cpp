// NaN and infinite voxels are "no data" (issue 31): left out of brick ranges, gradients and
// every sample walk; a sample with a non-finite corner is no data.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "random_volumes.hpp"
#include "slab/over.hpp"
#include "volume/brick_min_max.hpp"
#include "volume/brick_occupancy.hpp"
#include "volume/gradient_volume.hpp"
#include "volume/iso_crossing.hpp"
#include "volume/projection.hpp"
#include "volume/tf_emptiness.hpp"
#include "volume/volume_marcher.hpp"

namespace imx {
namespace {

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

bool finite(glm::vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
bool finite(glm::vec4 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

// A float volume of `dims` voxels holding field(i, j, k).
template <class Field>
std::shared_ptr<VolumeData> field_volume(glm::ivec3 dims, Field field) {
  auto data = std::make_shared<VolumeData>();
  data->dims = dims;
  std::vector<float> f;
  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i) f.push_back(field(i, j, k));
  data->voxels = std::move(f);
  return data;
}

TEST(NoData, TrilinearSamplesWithANonFiniteCornerAreNoData) {
  for (float bad : {kNan, kInf, -kInf}) {
    auto data = field_volume({4, 4, 4}, [&](int i, int, int) { return i == 2 ? bad : 1.0f * i; });
    AnyGrid g(*data);
    EXPECT_FALSE(no_data(g.sample({0.5f, 1.0f, 1.0f})));
    EXPECT_FALSE(no_data(g.sample({0.999f, 1.3f, 2.1f})));
    // On voxel plane 1 too: corner 2 has weight 0 there, but it is read (0 times NaN is NaN).
    for (float x : {1.0f, 1.5f, 2.0f, 2.7f, 3.0f})
      EXPECT_TRUE(no_data(g.sample({x, 1.2f, 1.7f}))) << bad << " at x " << x;
  }
  EXPECT_TRUE(no_data(kNan));
  EXPECT_TRUE(no_data(-kInf));
  EXPECT_FALSE(no_data(std::numeric_limits<float>::max()));
}

TEST(NoData, BrickRangesLeaveOutNonFiniteVoxels) {
  VolumeData vol;
  vol.dims = {9, 9, 9};
  std::vector<float> data(729, 0.0f);
  data[(5 * 9 + 5) * 9 + 5] = kNan;  // in brick (1, 1, 1) of 4 only
  data[(6 * 9 + 5) * 9 + 6] = kInf;
  data[(7 * 9 + 7) * 9 + 7] = -kInf;
  data[(6 * 9 + 6) * 9 + 6] = 3.0f;
  vol.voxels = data;
  BrickMinMax mm(AnyGrid(vol), glm::ivec3(4));
  EXPECT_EQ(mm.range({1, 1, 1}), glm::vec2(0.0f, 3.0f));
  EXPECT_TRUE(BrickMinMax::holds_data(mm.range({1, 1, 1})));
  EXPECT_EQ(mm.range({0, 0, 0}), glm::vec2(0.0f));
}

TEST(NoData, ABrickOfNoDataIsEmptyWhateverTheTf) {
  VolumeData vol;
  vol.dims = {9, 9, 9};
  std::vector<float> data(729, 1.0f);
  for (int k = 4; k < 9; ++k)  // brick (1, 1, 1) of 4 with its apron: voxels 4..8
    for (int j = 4; j < 9; ++j)
      for (int i = 4; i < 9; ++i) data[(k * 9 + j) * 9 + i] = (i + j + k) % 3 ? kNan : -kInf;
  vol.voxels = data;
  BrickMinMax mm(AnyGrid(vol), glm::ivec3(4));
  EXPECT_FALSE(BrickMinMax::holds_data(mm.range({1, 1, 1})));
  EXPECT_TRUE(BrickMinMax::holds_data(mm.range({0, 1, 1})));
  TransferFunction opaque;  // every value shows
  opaque.points = {{0.0, glm::vec4(1.0f)}};
  BrickOccupancy occ(mm, TfEmptiness(TfLut(opaque)));
  EXPECT_FALSE(occ.occupied({1, 1, 1}));
  EXPECT_TRUE(occ.occupied({0, 1, 1}));
  EXPECT_EQ(occ.occupied_count(), 7u);
}

// A linear field 2 i + j with a region of no data: the gradients at its boundary are finite and
// still point along the field, from one-sided differences.
TEST(NoData, GradientsAtANoDataBoundaryAreOneSided) {
  for (float bad : {kNan, kInf, -kInf}) {
    auto data = field_volume({8, 6, 5}, [&](int i, int j, int) {
      return i >= 5 ? bad : 2.0f * static_cast<float>(i) + static_cast<float>(j);
    });
    AnyGrid grid(*data);
    GradientVolume pre(grid);
    for (glm::vec3 p : {glm::vec3(4, 2, 2), glm::vec3(3.5f, 2.5f, 1.5f), glm::vec3(4, 0, 0)}) {
      const glm::vec3 g = pre.sample(p);
      ASSERT_TRUE(finite(g)) << bad;
      EXPECT_NEAR(g.x, 2.0f, 1e-3f) << "at " << p.x;
      EXPECT_NEAR(g.y, 1.0f, 1e-3f);
    }
    // Inside the no-data region a precomputed gradient is 0, never NaN.
    EXPECT_TRUE(finite(pre.sample({6.5f, 2.0f, 2.0f})));
    // On the fly, from trilinear samples: where the sample itself has data (x < 4; at x = 4 it
    // reads voxel 5), a side of no data makes the difference one-sided.
    for (glm::vec3 p :
         {glm::vec3(3.5f, 2.5f, 1.5f), glm::vec3(3.2f, 1, 3), glm::vec3(3.9f, 1, 2)}) {
      const glm::vec3 g = grid.gradient_of_data(p);
      ASSERT_TRUE(finite(g)) << bad;
      EXPECT_NEAR(g.x, 2.0f, 1e-4f) << "at " << p.x;
      EXPECT_NEAR(g.y, 1.0f, 1e-4f);
    }
    EXPECT_EQ(grid.gradient_of_data({4.0f, 2.0f, 2.0f}), glm::vec3(0.0f));
    EXPECT_EQ(grid.gradient_of_data({6.5f, 2.0f, 2.0f}), glm::vec3(0.0f));
    EXPECT_EQ(grid.gradient_of_data({2.0f, 2.0f, 2.0f}), grid.gradient({2.0f, 2.0f, 2.0f}));
  }
}

// A volume whose lower half along x holds data (value v) and whose upper half holds `bad`; a
// ray along x through both, at integer x when t = x + 10.
VolumeObject half_missing(float v, float bad, VolumeStyle style) {
  VolumeObject obj;
  obj.name = "half";
  obj.data = field_volume({16, 4, 4}, [&](int i, int, int) { return i < 8 ? v : bad; });
  obj.style = style;
  obj.iso_value = 0.5 * v;
  return obj;
}
const Ray kAlongX{{-10.0f, 1.5f, 1.5f}, {1.0f, 0.0f, 0.0f}};

TEST(NoData, MarchersComposeNothingOverNoData) {
  for (float bad : {kNan, kInf, -kInf})
    for (SkipMode skip : {SkipMode::none, SkipMode::distance})
      for (Classification c : {Classification::preintegrated, Classification::post}) {
        VolumeObject obj = half_missing(1.0f, bad, VolumeStyle::dvr);
        // Opaque everywhere, at the lowest value too: "NaN goes to entry 0" would show.
        obj.transfer_function.points = {{-5.0, glm::vec4(1, 0, 0, 0.5f)},
                                        {5.0, glm::vec4(0, 1, 0, 0.5f)}};
        obj.shading.enabled = true;
        MarchSettings s;
        s.skip = skip;
        s.classification = c;
        s.gradients = GradientSource::on_the_fly;
        const PreparedVolume v = test::prepared(obj, 0.5f, s);
        EXPECT_TRUE(v.has_no_data);
        const RayInterval span = v.intersect(kAlongX);
        ASSERT_FALSE(span.empty());
        VolumeMarcher m(v, kAlongX, span.t0, span.t1, 0.5f, {});
        Slab slab;
        int slabs = 0;
        glm::vec4 acc(0.0f);
        while (m.next(slab)) {
          ++slabs;
          EXPECT_LE(slab.t_back, 16.5f + 1e-4f) << "a slab reaching into no data";
          acc = over(acc, slab.color);
        }
        // Samples at x = 0, 0.5, ..., 6.5 have data (x = 7 reads voxel 8): 13 pieces between.
        EXPECT_EQ(slabs, 13);
        EXPECT_TRUE(finite(acc));
      }
}

TEST(NoData, ProjectionsAndIsoSurfacesSkipNoData) {
  MarchSettings skipping;
  for (float bad : {kNan, kInf, -kInf}) {
    // MIP: an infinite voxel is never the maximum; MinIP never the minimum.
    for (VolumeStyle style : {VolumeStyle::mip, VolumeStyle::minip}) {
      VolumeObject obj = half_missing(40.0f, bad, style);
      obj.transfer_function.points = {{0.0, glm::vec4(0.0f)}, {100.0, glm::vec4(1.0f)}};
      for (bool ranges : {false, true}) {
        PreparedVolume v = ranges ? test::prepared(obj, 0.5f, skipping) : PreparedVolume(obj);
        VolumeHit hit;
        const RayInterval span = v.intersect(kAlongX);
        ASSERT_TRUE(project_volume(v, kAlongX, span.t0, span.t1, 0.5, hit));
        EXPECT_NEAR(hit.color.a, 0.4f, 1e-3f) << bad;
        EXPECT_LT(hit.t, 17.0 + 1e-6);
      }
    }
    // X-ray: the no-data half adds no attenuation, even where the TF's lowest value is opaque.
    VolumeObject obj = half_missing(1.0f, bad, VolumeStyle::xray);
    obj.transfer_function.points = {{0.0, glm::vec4(0.5f)}, {2.0, glm::vec4(0.5f)}};
    obj.transfer_function.unit_distance = 1.0;
    PreparedVolume v(obj);
    VolumeHit hit;
    const RayInterval span = v.intersect(kAlongX);
    ASSERT_TRUE(project_volume(v, kAlongX, span.t0, span.t1, 0.5, hit));
    // mu = ln 2 per mm over the 6.5 mm between samples of data, and the trapezoid of the half
    // step to the first sample of no data, which counts as mu = 0 (as a hidden value would).
    EXPECT_NEAR(hit.color.a, 1.0f - std::exp2(-6.75f), 1e-4f) << bad;
    // Its average: the data's value over the data's length only.
    obj.xray_mode = XrayMode::average;
    obj.transfer_function.points = {{0.0, glm::vec4(0.0f)}, {2.0, glm::vec4(1.0f)}};
    PreparedVolume avg(obj);
    ASSERT_TRUE(project_volume(avg, kAlongX, span.t0, span.t1, 0.5, hit));
    EXPECT_NEAR(hit.color.a, 0.5f, 1e-4f) << bad;

    // Iso: no crossing where data meets no data, whichever side of the iso-value it is on.
    for (float value : {1.0f, -1.0f}) {
      VolumeObject iso = half_missing(value, bad, VolumeStyle::iso);
      iso.iso_value = 0.0;
      iso.transfer_function.points = {{-2.0, glm::vec4(1.0f)}, {2.0, glm::vec4(1.0f)}};
      for (bool ranges : {false, true}) {
        PreparedVolume pv = ranges ? test::prepared(iso, 0.5f, skipping) : PreparedVolume(iso);
        EXPECT_FALSE(find_iso_crossing(pv, kAlongX, span.t0, span.t1, 0.5, 10, {}, hit))
            << bad << " next to " << value;
      }
    }
  }
}

// A crossing next to no data is refined without stepping into it, and shaded with a finite
// normal.
TEST(NoData, IsoCrossingsBesideNoDataAreFinite) {
  VolumeObject obj;
  obj.name = "step";
  obj.data = field_volume({16, 4, 4}, [](int i, int j, int) {
    return i >= 8 ? kNan : (i < 6 ? -1.0f : 1.0f) + (j == 3 ? kNan : 0.0f);
  });
  obj.style = VolumeStyle::iso;
  obj.transfer_function.points = {{0.0, glm::vec4(1.0f)}};
  obj.shading.enabled = true;
  const PreparedVolume v(obj);
  const ShadingLight light;  // a headlight
  // At y = 1.9 the y difference of the normal reads voxel row 3: one-sided there.
  for (float y : {0.5f, 1.0f, 1.5f, 1.9f}) {
    const Ray ray{{-10.0f, y, 1.5f}, {1.0f, 0.0f, 0.0f}};
    const RayInterval span = v.intersect(ray);
    VolumeHit hit;
    ASSERT_TRUE(find_iso_crossing(v, ray, span.t0, span.t1, 0.25, 10, {&light, 1}, hit)) << y;
    EXPECT_NEAR(hit.t, 15.5, 0.01) << y;
    EXPECT_TRUE(finite(hit.color)) << y;
  }
}

}  // namespace
}  // namespace imx
