// zSlab pipeline kernels: RT rearrangement, the polygon stage with peeling and RT flushes, the
// deferred volume array, the hybrid cast and packed ZT storage, each on hand-made slabs.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "methods/zslab_buffer.hpp"
#include "methods/zslab_kernel.hpp"
#include "slab/mix.hpp"
#include "slab/over.hpp"

namespace imx {
namespace {

glm::vec4 grey(float a) {
  return glm::vec4(0.5f * a, 0.5f * a, 0.5f * a, a);
}

glm::vec4 composite(std::span<const Slab> s) {
  return accumulate(s, 1.0f).color;
}

bool sorted_disjoint(std::span<const Slab> s) {
  for (size_t k = 1; k < s.size(); ++k)
    if (s[k].front() < s[k - 1].t_back - 1e-5f) return false;
  return true;
}

// Replays a vector of slabs as a slab source.
struct VectorSource {
  std::vector<Slab> slabs;
  size_t next_index = 0;
  bool next(Slab& out) {
    if (next_index >= slabs.size()) return false;
    out = slabs[next_index++];
    return true;
  }
};

TEST(ZslabKernel, RearrangeSortsAndMixesOverlappingLayers) {
  // three virtual slabs out of order; [9,11] and [8,10] overlap on [9,10]
  Slab rt[3] = {{11.0f, 2.0f, grey(0.4f)}, {10.0f, 2.0f, grey(0.5f)}, {20.0f, 1.0f, grey(0.3f)}};
  Slab slots[kMaxRtLayers];
  SlabList out(slots);
  rearrange_layers(rt, out, {});
  ASSERT_EQ(out.size(), 3);  // [8,10] holding the mixed overlap, [10,11] the rest, [19,20]
  EXPECT_TRUE(sorted_disjoint(out.items()));
  EXPECT_FLOAT_EQ(out[0].t_back, 10.0f);
  EXPECT_FLOAT_EQ(out[0].thickness, 2.0f);
  EXPECT_FLOAT_EQ(out[1].t_back, 11.0f);
  EXPECT_FLOAT_EQ(out[2].t_back, 20.0f);
  float total = 1.0f - (1 - 0.5f) * (1 - 0.4f) * (1 - 0.3f);
  EXPECT_NEAR(composite(out.items()).a, total, 1e-5f);
}

TEST(ZslabKernel, RearrangeOverlapEqualsKernelMix) {
  // two aligned layers of different objects: one slab holding their mix
  Slab rt[2] = {{10.0f, 1.0f, grey(0.6f)}, {10.0f, 1.0f, glm::vec4(0.2f, 0.0f, 0.0f, 0.2f)}};
  Slab slots[kMaxRtLayers];
  SlabList out(slots);
  rearrange_layers(rt, out, {});
  ASSERT_EQ(out.size(), 1);
  glm::vec4 m = mix(rt[0].color, rt[1].color);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(out[0].color[i], m[i], 1e-6f);
}

Fragment frag(float t, float a, uint32_t object) {
  return Fragment{t, grey(a), object, 1u};
}

TEST(ZslabKernel, SurfaceStagePeelsAtMostLLayersPerObject) {
  ZslabParams p;
  p.peel_layers = 2;
  p.rt_layers = 4;
  p.mix.a_ert = 1.0f;
  float fixed[2] = {0.5f, 0.5f};
  StageThickness th{fixed};
  // object 0 has three surfaces, object 1 one: L = 2 drops object 0's third
  Fragment f[4] = {frag(10, 0.5f, 0), frag(20, 0.5f, 1), frag(30, 0.5f, 0), frag(40, 0.5f, 0)};
  Slab slots[8];
  SlabList out(slots);
  ASSERT_TRUE(run_surface_stage(f, th, {}, out, p));
  ASSERT_EQ(out.size(), 3);
  EXPECT_FLOAT_EQ(out[2].t_back, 30.0f);
  EXPECT_FLOAT_EQ(out[0].thickness, 0.5f);
  EXPECT_NEAR(composite(out.items()).a, 1.0f - 0.125f, 1e-6f);
}

TEST(ZslabKernel, SurfaceStageFlushesWhenRtLayersFill) {
  // M = 1: each layer is rearranged and intermixed on its own; the result is the same
  ZslabParams one, four;
  one.rt_layers = 1;
  one.mix.a_ert = four.mix.a_ert = 1.0f;
  float fixed[1] = {1.0f};
  StageThickness th{fixed};
  Fragment f[3] = {frag(10.0f, 0.4f, 0), frag(10.5f, 0.3f, 0), frag(14.0f, 0.6f, 0)};
  Slab stored[1] = {{12.0f, 4.0f, grey(0.5f)}};  // the surfaces lie inside a stored slab
  Slab a_slots[8], b_slots[8];
  SlabList a(a_slots), b(b_slots);
  ASSERT_TRUE(run_surface_stage(f, th, stored, a, one));
  ASSERT_TRUE(run_surface_stage(f, th, stored, b, four));
  EXPECT_TRUE(sorted_disjoint(a.items()));
  EXPECT_TRUE(sorted_disjoint(b.items()));
  float total = 1.0f - 0.6f * 0.7f * 0.4f * 0.5f;
  EXPECT_NEAR(composite(a.items()).a, total, 1e-5f);
  EXPECT_NEAR(composite(b.items()).a, total, 1e-5f);
}

TEST(ZslabKernel, SurfaceStageLeavesUntouchedSamples) {
  ZslabParams p;
  StageThickness th{};
  Slab slots[8];
  SlabList out(slots);
  out.push_back({5.0f, 1.0f, grey(0.5f)});
  EXPECT_FALSE(run_surface_stage({}, th, {}, out, p));
  EXPECT_EQ(out.size(), 1);
}

TEST(ZslabKernel, FootprintThicknessGrowsWithDepth) {
  StageThickness th{{}, 0.1f, 0.01f};
  EXPECT_FLOAT_EQ(th.of(0, 100.0f), 1.1f);
  float fixed[1] = {2.0f};
  StageThickness fixed_th{fixed, 0.1f, 0.01f};
  EXPECT_FLOAT_EQ(fixed_th.of(0, 100.0f), 2.0f);
}

TEST(ZslabKernel, VolumeArrayNeverExceedsNAndKeepsTheComposite) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<float> u(0.0f, 0.08f);
  for (int n : {4, 8, 16}) {
    VectorSource src;
    for (int k = 0; k < 200; ++k) src.slabs.push_back({1.0f + k, 1.0f, grey(u(gen))});
    glm::vec4 expected = composite(src.slabs);
    std::vector<Slab> slots(n);
    SlabList out(slots);
    collect_slabs(src, out, 1.0f);
    EXPECT_EQ(out.size(), n);
    EXPECT_TRUE(sorted_disjoint(out.items()));
    glm::vec4 got = composite(out.items());
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(got[i], expected[i], 1e-4f) << "N " << n;
    EXPECT_FLOAT_EQ(out[0].front(), 0.0f);
    EXPECT_FLOAT_EQ(out[n - 1].t_back, 200.0f);
  }
}

TEST(ZslabKernel, VolumeArrayStopsAtErt) {
  VectorSource src;
  for (int k = 0; k < 50; ++k) src.slabs.push_back({1.0f + k, 1.0f, grey(0.5f)});
  Slab slots[8];
  SlabList out(slots);
  collect_slabs(src, out, 0.9f);
  EXPECT_EQ(src.next_index, 4u);  // 1 - 0.5^4 = 0.9375 >= 0.9
}

TEST(ZslabKernel, HybridEqualsBatchIntermixAndStopsEarly) {
  Slab stored[2] = {{10.0f, 0.0f, grey(0.3f)}, {25.5f, 1.0f, grey(0.4f)}};
  VectorSource src;
  for (int k = 0; k < 40; ++k) src.slabs.push_back({5.0f + k, 1.0f, grey(0.1f)});
  IntermixSettings s;
  s.a_ert = 1.0f;
  Slab out_slots[64];
  SlabList batch(out_slots);
  IntermixResult r = intermix(std::span<const Slab>(stored), src.slabs, batch, s);
  VectorSource replay = src;
  glm::vec4 hybrid = trace_hybrid(stored, replay, s);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(hybrid[i], r.accumulated[i], 1e-6f);
  s.a_ert = 0.5f;
  VectorSource early = src;
  glm::vec4 stopped = trace_hybrid(stored, early, s);
  EXPECT_GE(stopped.a, 0.5f);
  EXPECT_LT(early.next_index, early.slabs.size());  // the march stopped at ERT
}

TEST(ZslabBuffer, PacksBothFormats) {
  Slab s[3] = {{1.0f, 0.5f, glm::vec4(0.1f, 0.2f, 0.3f, 0.4f)},
               {3.0f, 0.0f, glm::vec4(0.0f)},
               {7.0f, 2.0f, glm::vec4(0.001f, 0.0f, 0.002f, 0.004f)}};
  for (SlabFormat f : {SlabFormat::rgba32f, SlabFormat::rgba8}) {
    ZtBuffer b(2, 4, f);
    b.store(1, s);
    Slab back[4];
    ASSERT_EQ(b.load(0, back), 0);
    ASSERT_EQ(b.load(1, back), 3);
    float tol = f == SlabFormat::rgba8 ? 0.5f / 255.0f * 1.01f : 0.0f;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(back[k].t_back, s[k].t_back);
      EXPECT_EQ(back[k].thickness, s[k].thickness);
      EXPECT_NEAR(back[k].color.a, s[k].color.a, tol);
      // straight colour in 8 bits: premultiplied error scales with opacity
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(back[k].color[i], s[k].color[i], tol);
    }
    EXPECT_EQ(b.bytes(), 2u * 4u * static_cast<size_t>(slab_bytes(f)));
    b.store(1, std::span<const Slab>(s, 1));
    EXPECT_EQ(b.load(1, back), 1);
  }
}

}  // namespace
}  // namespace imx
