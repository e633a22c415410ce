// The per-ray kernels of the multi-fragment methods: dfb, dfb-sfm, kbuffer, peel, wboit, mboit.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "../slab/slab_test_util.hpp"
#include "homogeneous_volume.hpp"
#include "methods/fragment/dfb_kernel.hpp"
#include "methods/fragment/kbuffer_kernel.hpp"
#include "methods/fragment/mboit_kernel.hpp"
#include "methods/fragment/peel_kernel.hpp"
#include "methods/fragment/wboit_kernel.hpp"
#include "methods/reference/reference_kernel.hpp"
#include "slab/mix.hpp"

namespace imx {
namespace {

using test::near4;

// A ray's scratch arrays and the settings every kernel shares.
struct Fixture {
  std::vector<Slab> fragments = std::vector<Slab>(64), merged = std::vector<Slab>(8),
                    a = std::vector<Slab>(256), b = std::vector<Slab>(256),
                    resolved = std::vector<Slab>(kMaxKBufferSize + 1);
  HybridParams hp;
  Ray ray{{0, 0, 0}, {0, 0, 1}};
  Scene scene;
  SurfaceThickness zero, fixed;
  Fixture() {
    hp.ert = 1.0f;
    scene.order.assign(8, {ObjectKind::mesh, 0});
    scene.render.thickness = 0.5;
    CameraModel camera(scene.camera, 64, 64);
    zero = SurfaceThickness(scene, camera, true);
    fixed = SurfaceThickness(scene, camera, false);
  }
  glm::vec4 dfb(std::vector<Fragment> f, bool merge, std::span<const PreparedVolume> v = {}) {
    DfbParams p;
    p.merge = merge;
    return trace_dfb(ray, f, merge ? fixed : zero, v, {}, hp, p, {fragments, merged, {a, b}});
  }
  glm::vec4 kbuffer(const std::vector<Fragment>& f, int k, bool merge) {
    return trace_kbuffer(ray, f, merge ? fixed : zero, {}, {}, hp, {k, merge}, {resolved, {a, b}});
  }
  glm::vec4 peel(std::vector<Fragment> f, int layers, std::span<const PreparedVolume> v = {},
                 bool unsorted_rest = false) {
    return trace_peel(ray, f, {layers, unsorted_rest}, v, {}, hp, fragments, {a, b});
  }
};

glm::vec4 colour(float r, float g, float b, float a) {
  return {r * a, g * a, b * a, a};
}

std::vector<Fragment> layers(int n, std::mt19937& gen) {
  std::vector<Fragment> f;
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < n; ++i)
    f.push_back({10.0f + 4.0f * i, colour(u(gen), u(gen), u(gen), 0.2f + 0.5f * u(gen)),
                 uint32_t(i % 8), 1});
  std::shuffle(f.begin(), f.end(), gen);
  return f;
}

glm::vec4 exact(std::vector<Fragment> f) {
  std::sort(f.begin(), f.end(), [](const Fragment& a, const Fragment& b) { return a.t < b.t; });
  glm::vec4 c(0.0f);
  for (const Fragment& x : f) c = over(c, x.color);
  return c;
}

TEST(MultiFragmentKernels, SeparateLayersGiveExactOverInEveryMethodWithRoom) {
  Fixture fx;
  std::mt19937 gen(7);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Fragment> f = layers(6, gen);
    glm::vec4 want = exact(f);
    EXPECT_TRUE(near4(fx.dfb(f, false), want, 1e-6f));
    EXPECT_TRUE(near4(fx.dfb(f, true), want, 1e-6f));  // 4 mm apart: nothing to merge
    EXPECT_TRUE(near4(fx.kbuffer(f, 8, false), want, 1e-6f));
    EXPECT_TRUE(near4(fx.kbuffer(f, 6, true), want, 1e-6f));
    EXPECT_TRUE(near4(fx.peel(f, 6), want, 1e-6f));
  }
}

TEST(MultiFragmentKernels, PeelLosesLayersBeyondLAndCoplanarTies) {
  Fixture fx;
  std::vector<Fragment> f = {{10.0f, colour(1, 0, 0, 0.5f), 0, 1},
                             {10.0f, colour(0, 1, 0, 0.5f), 1, 1},
                             {20.0f, colour(0, 0, 1, 0.5f), 2, 1},
                             {30.0f, colour(1, 1, 1, 0.5f), 3, 1}};
  // layer 0 is the first in scene order at depth 10, layer 1 at depth 20; the rest is lost
  glm::vec4 want = over(f[0].color, f[2].color);
  EXPECT_TRUE(near4(fx.peel(f, 2), want, 1e-6f));
  std::reverse(f.begin(), f.end());
  EXPECT_TRUE(near4(fx.peel(f, 2), want, 1e-6f));
}

TEST(MultiFragmentKernels, PeelCanBlendTheRestInArrivalOrder) {
  Fixture fx;
  std::vector<Fragment> f = {{40.0f, colour(1, 1, 0, 0.5f), 4, 1},
                             {10.0f, colour(1, 0, 0, 0.5f), 0, 1},
                             {10.0f, colour(0, 1, 0, 0.5f), 1, 1},
                             {20.0f, colour(0, 0, 1, 0.5f), 2, 1},
                             {30.0f, colour(1, 1, 1, 0.5f), 3, 1}};
  // Two layers (red at 10, blue at 20); one more pass blends the fragments behind blue in the
  // order they arrived (yellow at 40 over white at 30). Green ties with red and stays lost.
  glm::vec4 want = over(over(f[1].color, f[3].color), over(f[0].color, f[4].color));
  EXPECT_TRUE(near4(fx.peel(f, 2, {}, true), want, 1e-6f));
  EXPECT_TRUE(near4(fx.peel(f, 2), over(f[1].color, f[3].color), 1e-6f));
  EXPECT_TRUE(near4(fx.peel(f, 5, {}, true), fx.peel(f, 5), 1e-6f));  // nothing left behind
}

TEST(MultiFragmentKernels, MergingMethodsBlendCoplanarSurfacesWhateverTheirOrder) {
  Fixture fx;
  Fragment red{50.0f, colour(1, 0, 0, 0.7f), 0, 1}, green{50.00001f, colour(0, 1, 0, 0.7f), 1, 1};
  std::vector<glm::vec4> both = {red.color, green.color};
  glm::vec4 blend = mix_m1(both);
  for (auto f : {std::vector<Fragment>{red, green}, std::vector<Fragment>{green, red}}) {
    EXPECT_TRUE(near4(fx.dfb(f, true), blend, 2e-3f));
    EXPECT_TRUE(near4(fx.kbuffer(f, 4, true), blend, 1e-6f));
    // the exact methods pick one order: the nearer by a rounding error wins
    EXPECT_TRUE(near4(fx.dfb(f, false), over(red.color, green.color), 1e-6f));
  }
}

TEST(MultiFragmentKernels, KBufferOverflowKeepsTotalOpacity) {
  Fixture fx;
  std::mt19937 gen(9);
  std::vector<Fragment> f = layers(20, gen);
  glm::vec4 want = exact(f);
  glm::vec4 k4 = fx.kbuffer(f, 4, false);
  EXPECT_NEAR(k4.a, want.a, 1e-5f);
  EXPECT_FALSE(near4(k4, want, 1e-4f));  // the tail is mixed, not sorted
  EXPECT_TRUE(near4(fx.kbuffer(f, 20, false), want, 1e-6f));
}

// Two surfaces inside a homogeneous medium on a ray that meets it over t in [90, 110], cast in
// steps of 1 mm, and the fine reference that answers for them.
struct SurfacesInAMedium : Fixture {
  VolumeObject obj = test::homogeneous_volume(0.1f, {0.2f, 0.4f, 1.0f});
  std::vector<PreparedVolume> vols{PreparedVolume(obj)};
  std::vector<Fragment> f = {{97.3f, colour(1, 0, 0, 0.6f), 0, 1},
                             {104.6f, colour(0, 1, 0, 0.5f), 1, 1}};
  SurfacesInAMedium() {
    ray = Ray{{0.3f, 0.2f, -100.0f}, {0, 0, 1}};
    hp.step = 1.0f;
  }
  glm::vec4 reference(std::vector<Fragment> surfaces) const {
    ReferenceParams rp;
    rp.step = 0.05;
    rp.ert = 1.0f;
    return trace_reference(ray, surfaces, vols, {}, rp);
  }
};

TEST(MultiFragmentKernels, SurfaceInsideAVolumeMatchesTheReference) {
  SurfacesInAMedium m;
  glm::vec4 ref = m.reference(m.f);
  EXPECT_TRUE(near4(m.dfb(m.f, false, m.vols), ref, 2e-3f));
  EXPECT_TRUE(near4(m.dfb(m.f, true, m.vols), ref, 2e-2f));  // 0.5 mm slabs blend with the medium
}

TEST(MultiFragmentKernels, PeelCompositesEachLayerAtTheNearestStepBoundary) {
  SurfacesInAMedium m;
  // Seed 001's depth test per sample: the layers land on the boundaries at 97 and 105 ...
  glm::vec4 peel = m.peel(m.f, 4, m.vols);
  EXPECT_TRUE(
      near4(peel, m.reference({{97.0f, m.f[0].color, 0, 1}, {105.0f, m.f[1].color, 1, 1}}), 2e-3f));
  // ... not at their exact depths (0.3 and 0.4 mm of medium move across them)
  EXPECT_FALSE(near4(peel, m.reference(m.f), 4e-3f));
  // peeling one layer loses the green surface but keeps the medium behind the red one
  glm::vec4 one = m.peel(m.f, 1, m.vols);
  EXPECT_LT(one.g, peel.g);
  EXPECT_NEAR(one.a, 1.0f - (1.0f - 0.6f) * std::pow(0.9f, 20.0f), 2e-3f);

  // The first step is cut at the entry: the volume now spans [90.5, 110.5], and a layer at 90.7
  // lands on 90.5 (in front of the medium), not on the grid point 91.
  m.ray.origin.z = -100.5f;
  glm::vec4 red = m.f[0].color;
  EXPECT_TRUE(
      near4(m.peel({{90.7f, red, 0, 1}}, 4, m.vols), m.reference({{90.5f, red, 0, 1}}), 2e-3f));
}

TEST(MultiFragmentKernels, WeightedBlendIsExactForOneLayerAndOrderIndependent) {
  DepthRange range{10.0f, 100.0f};
  std::mt19937 gen(11);
  std::vector<Fragment> f = layers(7, gen);
  Ray ray{{0, 0, 0}, {0, 0, 1}};
  HybridParams hp;
  glm::vec4 one = trace_wboit(ray, std::span(f).first(1), {}, {}, hp, range);
  EXPECT_TRUE(near4(one, f[0].color, 1e-6f));
  glm::vec4 all = trace_wboit(ray, f, {}, {}, hp, range);
  EXPECT_NEAR(all.a, exact(f).a, 1e-6f);
  std::reverse(f.begin(), f.end());
  EXPECT_TRUE(near4(trace_wboit(ray, f, {}, {}, hp, range), all, 1e-6f));
  EXPECT_GT(wboit_weight(0.5f, 0.1f), wboit_weight(0.5f, 0.6f));  // nearer weighs more
}

TEST(MultiFragmentKernels, MomentsApproximateSortedCompositing) {
  DepthRange range{10.0f, 100.0f};
  Ray ray{{0, 0, 0}, {0, 0, 1}};
  HybridParams hp;
  std::mt19937 gen(13);
  std::vector<Fragment> f = layers(1, gen);
  EXPECT_TRUE(near4(trace_mboit(ray, f, {}, {}, hp, range), f[0].color, 1e-5f));
  double worst = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    f = layers(5, gen);
    glm::vec4 m = trace_mboit(ray, f, {}, {}, hp, range);
    glm::vec4 want = exact(f);
    EXPECT_NEAR(m.a, want.a, 1e-5f);  // total opacity is exact
    for (int c = 0; c < 3; ++c) worst = std::max(worst, double(std::abs(m[c] - want[c])));
    std::reverse(f.begin(), f.end());
    EXPECT_TRUE(near4(trace_mboit(ray, f, {}, {}, hp, range), m, 1e-5f));
  }
  EXPECT_LT(worst, 0.1);
  // the transmittance bound falls with depth and stays in (0, 1]
  PowerMoments pm;
  for (float t : {20.0f, 40.0f, 60.0f}) pm.add(0.5f, moment_depth(t, range));
  double before = 1.0;
  for (float t : {15.0f, 30.0f, 50.0f, 80.0f}) {
    double tr = pm.transmittance_before(moment_depth(t, range));
    EXPECT_LE(tr, before + 1e-9);
    EXPECT_GT(tr, 0.0);
    before = tr;
  }
}

}  // namespace
}  // namespace imx
