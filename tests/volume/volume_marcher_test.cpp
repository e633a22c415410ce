#include "volume/volume_marcher.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "random_volumes.hpp"
#include "slab/over.hpp"
#include "volume/kept_span.hpp"

namespace imx {
namespace {

using test::prepared;
using test::random_ray;

struct MarchResult {
  std::vector<Slab> slabs;
  glm::vec4 composite{0.0f};
};

MarchResult march(const PreparedVolume& v, const Ray& ray, float step,
                  SlabExtent extent = SlabExtent::grid, std::span<const ShadingLight> lights = {}) {
  MarchResult r;
  RayInterval span = v.intersect(ray);
  if (span.empty()) return r;
  VolumeMarcher m(v, ray, span.t0, span.t1, step, lights, extent);
  Slab s;
  while (m.next(s)) {
    r.slabs.push_back(s);
    r.composite = over(r.composite, s.color);
  }
  return r;
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

// A volume `length` voxels long whose value is its x index, and a ray along x that meets voxel x
// at t = x + 10, so samples fall on integer x.
VolumeObject ramp_along_x(int length) {
  VolumeObject obj;
  obj.name = "ramp";
  obj.data = field_volume({length, 4, 4}, [](int i, int, int) { return static_cast<float>(i); });
  return obj;
}
const Ray kAlongX{{-10.0f, 1.5f, 1.5f}, {1.0f, 0.0f, 0.0f}};

// Skipping may only drop pieces that sampling would have found empty: with post-classification
// the slabs must be identical, with pre-integration the composite within table rounding.
TEST(VolumeMarcher, SkippingChangesNothingButTheWork) {
  std::mt19937 rng(7);
  int trials_with_empty_bricks = 0;
  for (int trial = 0; trial < 12; ++trial) {
    VolumeObject obj;
    obj.name = "blobs";
    obj.data = std::make_shared<VolumeData>(test::blob_volume<uint8_t>({37, 29, 33}, rng));
    obj.index_to_world = glm::dmat4(glm::dmat3(0.9, 0.1, 0.0, -0.1, 1.1, 0.0, 0.0, 0.2, 1.3));
    obj.transfer_function = test::random_tf(rng, 0.0f, 255.0f);
    for (Classification c : {Classification::post, Classification::preintegrated}) {
      MarchSettings plain{SkipMode::none, c, GradientSource::on_the_fly, 8};
      MarchSettings bricks = plain, distance = plain;
      bricks.skip = SkipMode::bricks;
      distance.skip = SkipMode::distance;
      distance.brick_size = 4;
      const float step = 0.7f;
      PreparedVolume vp = prepared(obj, step, plain), vb = prepared(obj, step, bricks),
                     vd = prepared(obj, step, distance);
      const BrickOccupancy& occ = *vd.accel.occupancy;
      trials_with_empty_bricks += occ.occupied_count() < occ.grid().count();
      for (int r = 0; r < 40; ++r) {
        Ray ray = random_ray(rng, glm::vec3(18, 20, 22), 30.0f);
        MarchResult p = march(vp, ray, step), b = march(vb, ray, step), d = march(vd, ray, step);
        if (c == Classification::post) {
          ASSERT_EQ(p.slabs.size(), b.slabs.size());
          ASSERT_EQ(p.slabs.size(), d.slabs.size());
          for (size_t i = 0; i < p.slabs.size(); ++i) {
            EXPECT_EQ(p.slabs[i].t_back, b.slabs[i].t_back);
            EXPECT_EQ(p.slabs[i].color, d.slabs[i].color);
          }
        }
        for (int k = 0; k < 4; ++k) {
          EXPECT_NEAR(p.composite[k], b.composite[k], 2e-3f);
          EXPECT_NEAR(p.composite[k], d.composite[k], 2e-3f);
        }
      }
    }
  }
  EXPECT_GT(trials_with_empty_bricks, 6);  // the comparison must have had something to skip
}

TEST(VolumeMarcher, SlabsAreSortedDisjointAndOnTheCommonGrid) {
  std::mt19937 rng(3);
  VolumeObject obj;
  obj.name = "blobs";
  obj.data = std::make_shared<VolumeData>(test::blob_volume<float>({24, 24, 24}, rng));
  obj.transfer_function.points = {{0.0, glm::vec4(1, 1, 1, 0.1f)}, {255.0, glm::vec4(1)}};
  const float step = 0.75f;
  PreparedVolume v = prepared(obj, step, {SkipMode::none, Classification::post});
  for (int r = 0; r < 50; ++r) {
    Ray ray = random_ray(rng, glm::vec3(12), 20.0f);
    RayInterval span = v.intersect(ray);
    MarchResult m = march(v, ray, step);
    if (span.empty()) continue;
    ASSERT_FALSE(m.slabs.empty());
    EXPECT_NEAR(m.slabs.front().front(), span.t0, 1e-4f);
    EXPECT_NEAR(m.slabs.back().t_back, span.t1, 1e-4f);
    for (size_t i = 0; i < m.slabs.size(); ++i) {
      const Slab& s = m.slabs[i];
      EXPECT_LE(s.thickness, step * 1.0001f);
      if (i > 0) {
        EXPECT_EQ(m.slabs[i - 1].t_back, s.front());  // contiguous: no value is transparent
      }
      if (i + 1 < m.slabs.size()) {
        float k = s.t_back / step;  // inner boundaries are grid points
        EXPECT_NEAR(k, std::round(k), 1e-3f);
      }
    }
  }
}

// Visible extents change where a slab lies, never what it holds: each slab is the same visibility
// as its grid piece, within it, and strictly narrower where the piece starts or ends transparent.
TEST(VolumeMarcher, VisibleExtentsNarrowSlabsWithinTheirPieces) {
  std::mt19937 rng(5);
  int narrowed = 0;
  for (int trial = 0; trial < 8; ++trial) {
    VolumeObject obj;
    obj.name = "blobs";
    obj.data = std::make_shared<VolumeData>(test::blob_volume<uint8_t>({31, 27, 29}, rng));
    obj.transfer_function = test::random_tf(rng, 0.0f, 255.0f);
    const float step = 0.8f;
    PreparedVolume v = prepared(obj, step, {SkipMode::distance, Classification::preintegrated});
    for (int r = 0; r < 40; ++r) {
      Ray ray = random_ray(rng, glm::vec3(15), 25.0f);
      MarchResult grid = march(v, ray, step), visible = march(v, ray, step, SlabExtent::visible);
      ASSERT_EQ(grid.slabs.size(), visible.slabs.size());
      for (size_t i = 0; i < grid.slabs.size(); ++i) {
        const Slab &g = grid.slabs[i], &s = visible.slabs[i];
        EXPECT_EQ(g.color, s.color);
        EXPECT_GE(s.front(), g.front() - 1e-4f);
        EXPECT_LE(s.t_back, g.t_back + 1e-4f);
        EXPECT_GE(s.thickness, g.thickness / 16.0f - 1e-5f);
        narrowed += s.thickness < 0.99f * g.thickness;
      }
    }
  }
  EXPECT_GT(narrowed, 100);
}

// A ramp along x crosses a TF spike between two samples: pre-integration sees it, post-
// classification at the step's mean value misses it. Both are judged by fine integration.
TEST(VolumeMarcher, PreintegrationFollowsASharpPeakPostClassificationMisses) {
  VolumeObject obj = ramp_along_x(64);
  obj.transfer_function.points = {{30.15, glm::vec4(1, 0.5f, 0, 0)},
                                  {30.25, glm::vec4(1, 0.5f, 0, 0.9f)},
                                  {30.35, glm::vec4(1, 0.5f, 0, 0)}};
  auto composite_at = [&](float step, Classification c) {
    return march(prepared(obj, step, {SkipMode::none, c}), kAlongX, step).composite;
  };
  glm::vec4 truth = composite_at(1.0f / 256.0f, Classification::post);
  ASSERT_GT(truth.a, 0.01f);
  glm::vec4 pre = composite_at(1.0f, Classification::preintegrated);
  glm::vec4 post = composite_at(1.0f, Classification::post);
  EXPECT_NEAR(pre.a, truth.a, 0.1f * truth.a);
  EXPECT_LT(std::abs(pre.a - truth.a), 0.2f * std::abs(post.a - truth.a));
}

// One headlit ray along x through `obj` (t = x + 10, a sample at every integer x), composited
// three ways: the truth (a fine post-classified march shaded at every tiny step), visible slabs
// and grid slabs shaded at their midpoints, both pre-integrated at a 1-voxel step.
struct ShadedMarches {
  glm::vec4 truth, visible, midpoint;
};
ShadedMarches shaded_marches(const VolumeObject& obj) {
  const ShadingLight headlight;
  Ray ray{{-10.0f, 4.0f, 1.5f}, {1.0f, 0.0f, 0.0f}};
  auto composite_at = [&](float step, Classification c, SlabExtent extent) {
    PreparedVolume v = prepared(obj, step, {SkipMode::none, c});
    return march(v, ray, step, extent, {&headlight, 1}).composite;
  };
  return {composite_at(1.0f / 64.0f, Classification::post, SlabExtent::grid),
          composite_at(1.0f, Classification::preintegrated, SlabExtent::visible),
          composite_at(1.0f, Classification::preintegrated, SlabExtent::grid)};
}

// Visible slabs are shaded where their light comes from. Along the ray (y = 4) the scalar is 2x
// and the normal turns with x (gradient (2, x - 14.9, 0)), facing the headlight at x = 14.9,
// where the TF turns opaque near the back of the step [14, 15]: shading that step at its
// midpoint sees a tilted normal.
TEST(VolumeMarcher, VisibleSlabsAreShadedAtTheirLightsCentre) {
  VolumeObject obj;
  obj.name = "turning ramp";
  obj.data = field_volume({64, 8, 4}, [](int i, int j, int) {
    return static_cast<float>(2 * i + (i - 14.9) * (j - 4));
  });
  obj.shading = {true, 0.0f, 1.0f, 0.0f, 1.0f};  // diffuse only: brightness is the normal's tilt
  obj.transfer_function.points = {{29.0, glm::vec4(1, 1, 1, 0)},
                                  {30.0, glm::vec4(1, 1, 1, 0.9f)},
                                  {80.0, glm::vec4(1, 1, 1, 0.9f)}};
  const ShadedMarches m = shaded_marches(obj);
  ASSERT_GT(m.truth.a, 0.5f);
  EXPECT_NEAR(m.visible.a, m.midpoint.a, 1e-6f);  // where it is shaded changes only the colour
  float centred_error = std::abs(m.visible.r - m.truth.r),
        midpoint_error = std::abs(m.midpoint.r - m.truth.r);
  EXPECT_GT(midpoint_error, 0.01f);
  EXPECT_LT(centred_error, 0.5f * midpoint_error)
      << m.truth.r << " " << m.visible.r << " " << m.midpoint.r;
}

// A thin medium spreads a step's light over the whole step, and the normal turns sharply within
// it: along the ray (y = 4) the gradient is (2, 8 (x - 14.5), 0), so the diffuse term peaks in
// the middle of the step [14, 15], to which clip planes cut the volume. One shading point at the
// light's centre (the middle) sees only the peak; the two-point quadrature over the light comes
// close to the fine march's average.
TEST(VolumeMarcher, SpreadLightIsShadedByTwoPointQuadrature) {
  VolumeObject obj;
  obj.name = "turning normal";
  obj.data = field_volume({64, 8, 4}, [](int i, int j, int) {
    return static_cast<float>(2 * i + 8 * (i - 14.5) * (j - 4));
  });
  obj.shading = {true, 0.0f, 1.0f, 0.0f, 1.0f};
  obj.transfer_function.points = {{-1000.0, glm::vec4(1, 1, 1, 0.05f)},
                                  {1000.0, glm::vec4(1, 1, 1, 0.05f)}};
  obj.clip_planes = {{glm::dvec3(14, 0, 0), glm::dvec3(1, 0, 0)},
                     {glm::dvec3(15, 0, 0), glm::dvec3(-1, 0, 0)}};
  const ShadedMarches m = shaded_marches(obj);
  ASSERT_GT(m.truth.a, 0.02f);
  auto brightness = [](glm::vec4 c) { return c.r / c.a; };
  float quadrature_error = std::abs(brightness(m.visible) - brightness(m.truth)),
        midpoint_error = std::abs(brightness(m.midpoint) - brightness(m.truth));
  EXPECT_GT(midpoint_error, 0.15f);
  EXPECT_LT(quadrature_error, 0.35f * midpoint_error)
      << brightness(m.truth) << " " << brightness(m.visible) << " " << brightness(m.midpoint);
}

// A visible slab is centred on its light: where the ramp enters an opaque medium mid-step, the
// slab starts near the entry and spans twice the distance to the opacity-weighted centre, so that
// an even spread of its opacity (what OVI splits) has the true first moment.
TEST(VolumeMarcher, VisibleSlabsAreCentredOnTheirLight) {
  VolumeObject obj = ramp_along_x(32);
  obj.transfer_function.points = {{10.25, glm::vec4(1, 1, 1, 0)},
                                  {10.35, glm::vec4(1, 1, 1, 0.95f)},
                                  {17.0, glm::vec4(1, 1, 1, 0.95f)},
                                  {22.0, glm::vec4(1, 1, 1, 0.1f)},
                                  {31.0, glm::vec4(1, 1, 1, 0.1f)}};
  PreparedVolume v = prepared(obj, 1.0f, {SkipMode::bricks, Classification::preintegrated});
  MarchResult r = march(v, kAlongX, 1.0f, SlabExtent::visible);  // pieces [x, x + 1]
  ASSERT_GT(r.slabs.size(), 15u);
  for (const Slab& s : r.slabs) {
    float x0 = std::ceil(s.t_back - 1e-4f) - 11.0f;  // the piece's front value s_f
    PreintegrationView::Light at;
    v.accel.preint->view().lookup(x0, x0 + 1.0f, at);
    float light = x0 + 10.0f + at.centre, mid = s.t_back - 0.5f * s.thickness;
    if (s.thickness > 1.0f / 16.0f + 1e-4f) {
      EXPECT_NEAR(mid, light, 1e-3f) << "piece at x " << x0;
    }
    if (x0 == 10.0f) {  // the entry: visible over its back 0.7, absorbed near its front
      EXPECT_GE(s.front(), 20.0f + 0.25f);
      EXPECT_LT(s.thickness, 0.65f);
    }
  }
}

// Clip geometry keeps pieces of a span: one marcher over the pieces gives exactly the slabs of one
// marcher per piece, one after the other, whatever it skipped in the gaps (the brick walk over the
// whole span serves every piece). Pieces reaching beyond the span are clamped to it.
TEST(VolumeMarcher, MarchingPiecesEqualsMarchingEachPiece) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int rays = 0, gaps_with_slabs = 0;
  for (int trial = 0; trial < 6; ++trial) {
    VolumeObject obj;
    obj.name = "blobs";
    obj.data = std::make_shared<VolumeData>(test::blob_volume<uint8_t>({37, 29, 33}, rng));
    obj.index_to_world = glm::dmat4(glm::dmat3(0.9, 0.1, 0.0, -0.1, 1.1, 0.0, 0.0, 0.2, 1.3));
    obj.transfer_function = test::random_tf(rng, 0.0f, 255.0f);
    obj.shading.enabled = trial % 2 == 0;
    for (SkipMode skip : {SkipMode::none, SkipMode::distance})
      for (Classification c : {Classification::post, Classification::preintegrated}) {
        const float step = 0.7f;
        const PreparedVolume v = prepared(
            obj, step, {skip, c, GradientSource::on_the_fly, skip == SkipMode::none ? 8 : 4});
        const ShadingLight light = resolve_light(Light{});
        for (int r = 0; r < 30; ++r) {
          const Ray ray = random_ray(rng, glm::vec3(18, 20, 22), 30.0f);
          const RayInterval span = v.intersect(ray);
          if (span.empty()) continue;
          ++rays;
          // Up to 8 random pieces from just before the span to just past it.
          ClipPieces clip;
          std::vector<float> cuts;
          const int n = 1 + static_cast<int>(u(rng) * 2 * kMaxClipPieces);
          const float len = span.t1 - span.t0;
          for (int k = 0; k < n; ++k) cuts.push_back(span.t0 - 0.1f * len + 1.2f * len * u(rng));
          std::sort(cuts.begin(), cuts.end());
          for (size_t k = 0; k + 1 < cuts.size(); k += 2) clip.add(cuts[k], cuts[k + 1]);
          const KeptSpan kept(span, clip);
          for (SlabExtent extent : {SlabExtent::grid, SlabExtent::visible}) {
            std::vector<Slab> whole, each;
            VolumeMarcher m(v, ray, kept, step, {&light, 1}, extent);
            for (Slab s; m.next(s);) whole.push_back(s);
            for (int k = 0; k < kept.size(); ++k) {
              VolumeMarcher one(v, ray, kept[k].t0, kept[k].t1, step, {&light, 1}, extent);
              for (Slab s; one.next(s);) each.push_back(s);
            }
            ASSERT_EQ(whole.size(), each.size());
            for (size_t i = 0; i < whole.size(); ++i) {
              EXPECT_EQ(whole[i].t_back, each[i].t_back);
              EXPECT_EQ(whole[i].thickness, each[i].thickness);
              EXPECT_EQ(whole[i].color, each[i].color);
              EXPECT_TRUE(kept.contains(whole[i].t_back - 0.5f * whole[i].thickness));
            }
            // The gaps held something that was not marched (else the test proves little).
            if (extent == SlabExtent::grid && march(v, ray, step).slabs.size() > whole.size())
              ++gaps_with_slabs;
          }
        }
      }
  }
  EXPECT_GT(rays, 200);
  EXPECT_GT(gaps_with_slabs, 100);
}

}  // namespace
}  // namespace imx
