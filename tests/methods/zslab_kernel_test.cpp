// zSlab pipeline kernels: RT rearrangement, the polygon stage with peeling and RT flushes, the
// deferred volume array and the hybrid cast, each on hand-made slabs.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "methods/zslab/zslab_kernel.hpp"
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
    collect_slabs(src, out, 1.0f, Overflow::greedy);
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
  collect_slabs(src, out, 0.9f, Overflow::greedy);
  EXPECT_EQ(src.next_index, 4u);  // 1 - 0.5^4 = 0.9375 >= 0.9
}

// 200 unit slabs of varying density: far more than any N, so every policy must fold.
VectorSource many_slabs() {
  std::mt19937 gen(11);
  std::uniform_real_distribution<float> u(0.0f, 0.08f);
  VectorSource src;
  for (int k = 0; k < 200; ++k) src.slabs.push_back({1.0f + k, 1.0f, grey(u(gen))});
  return src;
}

TEST(ZslabKernel, VolumeArrayTailKeepsTheFirstSlabsAndFoldsTheRest) {
  VectorSource src = many_slabs();
  glm::vec4 expected = composite(src.slabs);
  const int n = 4;
  std::vector<Slab> slots(n);
  SlabList tail(slots);
  collect_slabs(src, tail, 1.0f, Overflow::tail);
  ASSERT_EQ(tail.size(), n);
  for (int k = 0; k + 1 < n; ++k) {  // tail handling leaves the first N - 1 slabs alone
    EXPECT_EQ(tail[k].t_back, src.slabs[k].t_back);
    EXPECT_EQ(tail[k].color, src.slabs[k].color);
  }
  EXPECT_FLOAT_EQ(tail[n - 1].front(), src.slabs[n - 1].front());
  EXPECT_FLOAT_EQ(tail[n - 1].t_back, 200.0f);
  glm::vec4 got = composite(tail.items());
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(got[i], expected[i], 1e-4f);

  VectorSource again = many_slabs();
  std::vector<Slab> greedy_slots(n);
  SlabList greedy(greedy_slots);
  collect_slabs(again, greedy, 1.0f, Overflow::greedy);
  EXPECT_NE(greedy[0].t_back, tail[0].t_back);  // greedy merges early slabs too
}

// Intermixing into a full output under either policy writes only the N slots it was given and
// keeps the composite; tail keeps the kernel's first N - 1 emitted slabs exactly.
TEST(ZslabKernel, StageOverflowStaysWithinCapacity) {
  VectorSource src = many_slabs();
  std::vector<Slab> stored;
  for (int k = 0; k < 4; ++k) stored.push_back({20.5f + 40.0f * k, 3.0f, grey(0.3f)});
  IntermixSettings s;
  s.a_ert = 1.0f;
  std::vector<Slab> unbounded_slots(512);
  SlabList unbounded(unbounded_slots);
  IntermixResult all = intermix(std::span<const Slab>(stored), src.slabs, unbounded, s);
  ASSERT_GT(unbounded.size(), 8);
  const int n = 4;
  const Slab sentinel{-1.0f, -7.0f, glm::vec4(9.0f)};
  std::vector<Slab> results[2];
  for (Overflow o : {Overflow::tail, Overflow::greedy}) {
    std::vector<Slab> slots(n + 4, sentinel);
    SlabList out(std::span<Slab>(slots.data(), n));
    s.overflow = o;
    intermix_stage(stored, src.slabs, out, s);
    EXPECT_EQ(out.size(), n);
    for (int k = n; k < n + 4; ++k) EXPECT_EQ(slots[k].color, sentinel.color) << "slot " << k;
    EXPECT_TRUE(sorted_disjoint(out.items()));
    glm::vec4 got = composite(out.items());
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(got[i], all.accumulated[i], 1e-4f);
    EXPECT_FLOAT_EQ(out[n - 1].t_back, unbounded[unbounded.size() - 1].t_back);
    results[o == Overflow::tail ? 0 : 1].assign(out.begin(), out.end());
  }
  for (int k = 0; k + 1 < n; ++k) {
    EXPECT_EQ(results[0][k].t_back, unbounded[k].t_back);
    EXPECT_EQ(results[0][k].color, unbounded[k].color);
  }
  bool differ = false;
  for (int k = 0; k < n; ++k) differ |= results[0][k].t_back != results[1][k].t_back;
  EXPECT_TRUE(differ) << "tail and greedy folded the same way";
}

TEST(ZslabKernel, SurfaceStageFoldsAsTheSettingsSay) {
  // ten surfaces of one object through a stage of N = 4 slabs; the two faint touching ones in
  // front are the cheapest pair for greedy merging, tail handling folds the deep end instead
  std::vector<Fragment> fragments = {frag(10.0f, 0.02f, 0), frag(11.0f, 0.02f, 0)};
  for (int k = 2; k < 10; ++k) fragments.push_back(frag(10.0f * k, 0.3f, 0));
  float thickness[1] = {1.0f};
  StageThickness th{thickness, 0.0f, 0.0f};
  ZslabParams p;
  p.layers = 4;
  p.rt_layers = 4;
  p.peel_layers = 16;
  p.mix.a_ert = 1.0f;
  std::vector<Slab> results[2];
  for (Overflow o : {Overflow::tail, Overflow::greedy}) {
    p.mix.overflow = o;
    Slab slots[4];
    SlabList out(slots);
    ASSERT_TRUE(run_surface_stage(fragments, th, {}, out, p));
    EXPECT_EQ(out.size(), 4);
    EXPECT_TRUE(sorted_disjoint(out.items()));
    results[o == Overflow::tail ? 0 : 1].assign(out.begin(), out.end());
  }
  const float kept[3] = {10.0f, 11.0f, 20.0f};
  for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(results[0][k].t_back, kept[k]);
  EXPECT_FLOAT_EQ(results[0][3].front(), 29.0f);  // the 4th surface onwards in the tail
  EXPECT_FLOAT_EQ(results[0][3].t_back, 90.0f);
  EXPECT_FLOAT_EQ(results[1][0].front(), 9.0f);  // greedy merged the faint pair instead
  EXPECT_FLOAT_EQ(results[1][0].t_back, 11.0f);
  EXPECT_NEAR(composite(results[0]).a, composite(results[1]).a, 1e-5f);
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

}  // namespace
}  // namespace imx
