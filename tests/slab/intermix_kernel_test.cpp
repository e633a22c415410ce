#include <gtest/gtest.h>

#include <vector>

#include "slab/accumulate.hpp"
#include "slab/intermix_kernel.hpp"
#include "slab/mix.hpp"
#include "slab/sfm.hpp"
#include "slab/split.hpp"
#include "slab_test_util.hpp"

namespace imx {
namespace {

using test::near4;
using test::near_slab;

using Out = SlabArray<64>;

// No ERT, every slab kept: the kernel's output is then fully determined by its inputs.
IntermixSettings exact(Interpolation mode = Interpolation::ovi) {
  IntermixSettings s;
  s.interpolation.mode = mode;
  s.a_ert = 1.0f;
  s.skip_empty = false;
  return s;
}

Out run(const std::vector<Slab>& p, const std::vector<Slab>& q, const IntermixSettings& s) {
  Out out;
  intermix(p, q, out, s);
  return out;
}

glm::vec4 red(float a) {
  return {a, 0, 0, a};
}
glm::vec4 green(float a) {
  return {0, a, 0, a};
}
glm::vec4 blue(float a) {
  return {0, 0, a, a};
}

float opacity_product(const std::vector<Slab>& a, const std::vector<Slab>& b) {
  float t = 1.0f;
  for (const Slab& s : a) t *= 1.0f - s.color.a;
  for (const Slab& s : b) t *= 1.0f - s.color.a;
  return 1.0f - t;
}

// Both argument orders must give the same output (the kernel is symmetric in P and Q).
void expect_both_orders(const std::vector<Slab>& p, const std::vector<Slab>& q,
                        const std::vector<Slab>& expect, IntermixSettings s = exact()) {
  for (int order = 0; order < 2; ++order) {
    Out out = order == 0 ? run(p, q, s) : run(q, p, s);
    ASSERT_EQ(out.size(), int(expect.size())) << "order " << order;
    for (int i = 0; i < out.size(); ++i)
      EXPECT_TRUE(near_slab(out[i], expect[i], 1e-6f)) << "order " << order << " slab " << i;
  }
}

TEST(IntermixKernel, DisjointSlabsPassThroughInDepthOrder) {
  Slab p{1.0f, 1.0f, red(0.5f)}, q{3.0f, 1.0f, green(0.5f)};
  expect_both_orders({p}, {q}, {p, q});
  // touching slabs are disjoint too
  Slab t{2.0f, 1.0f, blue(0.5f)};
  expect_both_orders({p}, {t}, {p, t});
}

TEST(IntermixKernel, PartialOverlapOviHandComputed) {
  // p = [0, 2], q = [1, 3], A = 1/2 each. OVI halves: p_f = 1/4, p_o = 1/3 (inverted),
  // q_o = 1/4, q_b = 1/3. fused = mix(p_o, q_o) = (7/24, 5/24, 0, 1/2);
  // integrated = p_f over fused = (15/32, 5/32, 0, 5/8) on [0, 2]; remaining q_b on [2, 3].
  Slab p{2.0f, 2.0f, red(0.5f)}, q{3.0f, 2.0f, green(0.5f)};
  expect_both_orders({p}, {q},
                     {Slab{2.0f, 2.0f, {15.0f / 32.0f, 5.0f / 32.0f, 0, 0.625f}},
                      Slab{3.0f, 1.0f, green(1.0f / 3.0f)}});
}

TEST(IntermixKernel, PartialOverlapHviHandComputed) {
  // A = 3/4 over 2 mm: each homogeneous half has A = 1/2. fused = mix of two halves
  // = (3/8, 0, 3/8, 3/4); integrated = (1/2 red) over fused = (11/16, 0, 3/16, 7/8).
  Slab p{2.0f, 2.0f, red(0.75f)}, q{3.0f, 2.0f, blue(0.75f)};
  expect_both_orders(
      {p}, {q},
      {Slab{2.0f, 2.0f, {11.0f / 16.0f, 0, 3.0f / 16.0f, 0.875f}}, Slab{3.0f, 1.0f, blue(0.5f)}},
      exact(Interpolation::hvi));
}

TEST(IntermixKernel, ContainmentOviHandComputed) {
  // q = [0, 4] contains p = [1, 2]. q split front to back: q_f = 1/8 on [0, 1], the rest
  // 3/7 on [1, 4], split again: q_m = 1/7 on [1, 2], q_b = 1/3 on [2, 4].
  // fused = mix(p, q_m) = (13/28, 3/28, 0, 4/7); integrated = q_f over fused
  // = (13/32, 7/32, 0, 5/8) on [0, 2].
  Slab p{2.0f, 1.0f, red(0.5f)}, q{4.0f, 4.0f, green(0.5f)};
  expect_both_orders({p}, {q},
                     {Slab{2.0f, 2.0f, {13.0f / 32.0f, 7.0f / 32.0f, 0, 0.625f}},
                      Slab{4.0f, 2.0f, green(1.0f / 3.0f)}});
}

TEST(IntermixKernel, AlignedSlabsAreMixed) {
  Slab p{2.0f, 1.0f, red(0.5f)}, q{2.0f, 1.0f, green(0.5f)};
  expect_both_orders({p}, {q}, {Slab{2.0f, 1.0f, mix(p.color, q.color)}});
  // coplanar surfaces are aligned as well: no z-fighting, an even blend
  Slab s1{5.0f, 0.0f, red(1.0f)}, s2{5.0f, 0.0f, blue(1.0f)};
  expect_both_orders({s1}, {s2}, {Slab{5.0f, 0.0f, {0.5f, 0, 0.5f, 1.0f}}});
}

TEST(IntermixKernel, EqualBacksMergeIntoOneSlab) {
  // [0, 2] and [1, 2]: the thicker one is split at 1; its back half mixes with the other.
  // p_f = 1/4 red, p_o = 1/3 red; fused = (1/4, 5/12, 0, 2/3); integrated = (7/16, 5/16, 0, 3/4)
  Slab p{2.0f, 2.0f, red(0.5f)}, q{2.0f, 1.0f, green(0.5f)};
  expect_both_orders({p}, {q}, {Slab{2.0f, 2.0f, {7.0f / 16.0f, 5.0f / 16.0f, 0, 0.75f}}});
}

TEST(IntermixKernel, SurfaceInsideASlabSplitsIt) {
  Slab vol{2.0f, 2.0f, {0.25f, 0.25f, 0.25f, 0.5f}}, surface{1.0f, 0.0f, red(0.5f)};
  for (auto mode : {Interpolation::ovi, Interpolation::hvi}) {
    SlabParts parts = split_at_depth(vol, 1.0f, {mode});
    expect_both_orders({vol}, {surface},
                       {Slab{1.0f, 1.0f, over(parts.front.color, surface.color)}, parts.back},
                       exact(mode));
  }
}

TEST(IntermixKernel, SurfaceOnABoundaryStaysASlabOfItsOwn) {
  Slab vol{2.0f, 2.0f, green(0.5f)};
  Slab at_front{0.0f, 0.0f, red(0.5f)}, at_back{2.0f, 0.0f, red(0.5f)};
  expect_both_orders({vol}, {at_front}, {at_front, vol});
  expect_both_orders({vol}, {at_back}, {vol, at_back});
}

TEST(IntermixKernel, WithoutOverlapTheOutputIsTheMergedSortedInput) {
  test::SlabRng rng(41);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<Slab> all = rng.disjoint_sequence(rng.integer(0, 20), rng.grid(-5.0f, 5.0f));
    std::vector<Slab> p, q;
    test::deal(rng, all, p, q);
    Out out = run(p, q, exact(Interpolation(rng.integer(0, 2))));
    ASSERT_EQ(out.size(), int(all.size()));
    for (int i = 0; i < out.size(); ++i) EXPECT_TRUE(near_slab(out[i], all[i], 0.0f)) << i;
    EXPECT_TRUE(near4(out.accumulate(1.0f).color, accumulate(all, 1.0f).color, 0.0f));
  }
}

// P and Q each sorted and disjoint, overlapping each other anywhere.
void random_pair(test::SlabRng& rng, std::vector<Slab>& p, std::vector<Slab>& q) {
  p = rng.disjoint_sequence(rng.integer(0, 12), rng.grid(0.0f, 3.0f));
  q = rng.disjoint_sequence(rng.integer(0, 12), rng.grid(0.0f, 3.0f));
}

TEST(IntermixKernel, RandomOverlapsKeepOrderCountOpacityAndSymmetry) {
  test::SlabRng rng(42);
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<Slab> p, q;
    random_pair(rng, p, q);
    IntermixSettings s = exact(Interpolation(rng.integer(0, 2)));
    s.interpolation.beta = rng.uniform(0.0f, 1.0f);
    Out out = run(p, q, s);
    Out swapped = run(q, p, s);
    ASSERT_LE(out.size(), int(p.size() + q.size()));
    ASSERT_EQ(out.size(), swapped.size());
    for (int i = 0; i < out.size(); ++i) {
      EXPECT_TRUE(near_slab(out[i], swapped[i], 1e-6f)) << "trial " << trial << " slab " << i;
      EXPECT_GE(out[i].thickness, 0.0f);
      if (i > 0) {
        EXPECT_LE(out[i - 1].t_back, out[i].t_back);
        EXPECT_GE(out[i].front(), out[i - 1].t_back - 1e-5f) << "outputs overlap";
      }
    }
    // splitting, mix and over all multiply transmittances: total opacity is conserved
    EXPECT_NEAR(out.accumulate(1.0f).color.a, opacity_product(p, q), 2e-5f) << "trial " << trial;
    if (!p.empty() || !q.empty()) {
      float lo = p.empty()   ? q[0].front()
                 : q.empty() ? p[0].front()
                             : std::min(p[0].front(), q[0].front());
      float hi = p.empty()   ? q.back().t_back
                 : q.empty() ? p.back().t_back
                             : std::max(p.back().t_back, q.back().t_back);
      EXPECT_NEAR(out[0].front(), lo, 1e-5f);
      EXPECT_EQ(out[out.size() - 1].t_back, hi);
    }
  }
}

TEST(IntermixKernel, EmptySlabsTakeNoSlot) {
  test::SlabRng rng(43);
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<Slab> p = rng.disjoint_sequence(rng.integer(1, 10));
    std::vector<Slab> q = rng.disjoint_sequence(rng.integer(1, 10));
    for (Slab& s : q) s.color = glm::vec4(0.0f);
    std::vector<Slab> visible;
    for (const Slab& s : p)
      if (!s.is_empty()) visible.push_back(s);
    IntermixSettings s;
    s.a_ert = 1.0f;  // skip_empty stays on
    Out out = run(p, q, s);
    ASSERT_EQ(out.size(), int(visible.size()));
    for (int i = 0; i < out.size(); ++i) EXPECT_TRUE(near_slab(out[i], visible[i], 0.0f));
  }
}

TEST(IntermixKernel, SinkCapacityIsNeverExceeded) {
  test::SlabRng rng(44);
  for (Overflow o : {Overflow::tail, Overflow::greedy})
    for (int trial = 0; trial < 300; ++trial) {
      std::vector<Slab> p, q;
      random_pair(rng, p, q);
      IntermixSettings s = exact();
      s.overflow = o;
      SlabArray<3> small;
      IntermixResult r = intermix(p, q, small, s);
      Out full = run(p, q, s);
      ASSERT_LE(small.size(), 3);
      EXPECT_EQ(small.size(), std::min(full.size(), 3));
      EXPECT_TRUE(near4(small.accumulate(1.0f).color, full.accumulate(1.0f).color, 2e-6f));
      EXPECT_TRUE(near4(r.accumulated, full.accumulate(1.0f).color, 2e-6f));
      std::vector<Slab> storage(2);
      SlabList list(storage);
      intermix(p, q, list, s);
      ASSERT_LE(list.size(), 2);
      EXPECT_TRUE(near4(list.accumulate(1.0f).color, full.accumulate(1.0f).color, 2e-6f));
    }
}

TEST(IntermixKernel, EarlyRayTerminationStopsAtTheThreshold) {
  std::vector<Slab> p, q;
  for (int k = 0; k < 10; ++k) {
    p.push_back(Slab{2.0f * k + 1.0f, 1.0f, red(0.5f)});
    q.push_back(Slab{2.0f * k + 2.0f, 1.0f, green(0.5f)});
  }
  IntermixSettings s = exact();
  s.a_ert = 0.9f;
  Out out;
  IntermixResult r = intermix(p, q, out, s);
  EXPECT_TRUE(r.terminated);
  ASSERT_EQ(out.size(), 4);  // 1 - 2^-4 = 0.9375 is the first opacity >= 0.9
  EXPECT_FLOAT_EQ(r.accumulated.a, 0.9375f);
  EXPECT_LT(accumulate(std::span<const Slab>(out.items().first(3)), 1.0f).color.a, 0.9f);

  // streaming: push() reports the termination so a ray caster stops marching
  Out streamed;
  Intermixer<Out> kernel(p, streamed, s);
  int pushed = 0;
  for (const Slab& slab : q) {
    ++pushed;
    if (!kernel.push(slab)) break;
  }
  kernel.finish();
  EXPECT_TRUE(kernel.terminated());
  EXPECT_EQ(pushed, 2);
  ASSERT_EQ(streamed.size(), 4);
  EXPECT_FALSE(kernel.push(q[5]));
  EXPECT_EQ(streamed.size(), 4);

  // without ERT everything is emitted
  EXPECT_EQ(run(p, q, exact()).size(), 20);
  // ERT inside an integrated slab: an opaque stored slab ends the ray
  Out opaque;
  IntermixResult o = intermix(std::vector<Slab>{Slab{2.0f, 2.0f, red(1.0f)}},
                              std::vector<Slab>{Slab{3.0f, 2.0f, green(0.5f)}, q[8]}, opaque);
  EXPECT_TRUE(o.terminated);
  EXPECT_EQ(opaque.size(), 1);
}

TEST(IntermixKernel, StreamingEqualsBatch) {
  test::SlabRng rng(45);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Slab> p, q;
    random_pair(rng, p, q);
    IntermixSettings s = exact(Interpolation::blend);
    s.interpolation.beta = 0.5f;
    Out batch = run(p, q, s), streamed;
    Intermixer<Out> kernel(p, streamed, s);
    for (const Slab& slab : q) kernel.push(slab);
    kernel.finish();
    ASSERT_EQ(batch.size(), streamed.size());
    // equal up to how the compiler contracts multiply-adds in each inlined copy
    for (int i = 0; i < batch.size(); ++i) EXPECT_TRUE(near_slab(batch[i], streamed[i], 1e-6f));
  }
}

TEST(Sfm, MergesTwoFragmentsIntoOneOverTheirUnion) {
  InSlabInterpolation ovi{Interpolation::ovi};
  Slab p{2.0f, 2.0f, red(0.5f)}, q{3.0f, 2.0f, green(0.5f)};
  // integrated (15/32, 5/32, 0, 5/8) over remaining (0, 1/3, 0, 1/3)
  Slab expect{3.0f, 3.0f, {15.0f / 32.0f, 9.0f / 32.0f, 0, 0.75f}};
  EXPECT_TRUE(near_slab(sfm(p, q, ovi), expect, 1e-6f));
  EXPECT_TRUE(near_slab(sfm(q, p, ovi), expect, 1e-6f));
  // aligned: mix; disjoint: over, spanning the gap too
  EXPECT_TRUE(near_slab(sfm(p, Slab{2.0f, 2.0f, green(0.5f)}, ovi),
                        Slab{2.0f, 2.0f, mix(red(0.5f), green(0.5f))}, 1e-7f));
  Slab far{9.0f, 1.0f, green(0.5f)};
  EXPECT_TRUE(near_slab(sfm(far, p, ovi), Slab{9.0f, 9.0f, over(p.color, far.color)}, 1e-7f));
}

TEST(Sfm, BetaControlsTheOverlapBlend) {
  Slab p{2.0f, 2.0f, red(0.99f)}, q{3.0f, 2.0f, blue(0.99f)};
  // with nearly opaque fragments, OVI lets the back fragment show through much more than HVI
  float blue_ovi = sfm(p, q, {Interpolation::blend, 1.0f}).color.b;
  float blue_mid = sfm(p, q, {Interpolation::blend, 0.5f}).color.b;
  float blue_hvi = sfm(p, q, {Interpolation::blend, 0.0f}).color.b;
  EXPECT_GT(blue_ovi, blue_mid);
  EXPECT_GT(blue_mid, blue_hvi);
  EXPECT_NEAR(sfm(p, q, {Interpolation::blend, 0.0f}).color.a,
              sfm(p, q, {Interpolation::ovi}).color.a, 1e-6f);
}

}  // namespace
}  // namespace imx
