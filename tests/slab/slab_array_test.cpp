#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "slab/greedy_merge.hpp"
#include "slab/slab_array.hpp"
#include "slab_test_util.hpp"

namespace imx {
namespace {

using test::near4;
using test::near_slab;

glm::vec4 gray(float a) {
  return {0.5f * a, 0.5f * a, 0.5f * a, a};
}

std::vector<Slab> sorted(std::vector<Slab> v) {
  std::stable_sort(v.begin(), v.end(), [](const Slab& a, const Slab& b) {
    return a.t_back < b.t_back || (a.t_back == b.t_back && a.front() < b.front());
  });
  return v;
}

bool is_sorted(std::span<const Slab> s) {
  for (size_t i = 1; i < s.size(); ++i)
    if (s[i].t_back < s[i - 1].t_back) return false;
  return true;
}

TEST(SlabArray, InsertKeepsBackDepthOrder) {
  test::SlabRng rng(31);
  for (int trial = 0; trial < 100; ++trial) {
    SlabArray<16> arr;
    std::vector<Slab> all;
    for (int i = 0; i < 16; ++i) {
      Slab s{rng.grid(0.0f, 10.0f), rng.grid(0.0f, 2.0f), rng.visibility()};
      all.push_back(s);
      arr.insert(s);
    }
    ASSERT_EQ(arr.size(), 16);
    std::vector<Slab> expect = sorted(all);
    for (int i = 0; i < 16; ++i) EXPECT_TRUE(near_slab(arr[i], expect[i], 0.0f)) << i;
  }
}

TEST(SlabArray, PushBackFoldsTheExcessIntoTheTail) {
  SlabArray<2> arr;
  arr.push_back(Slab{1.0f, 1.0f, gray(0.5f)});
  arr.push_back(Slab{2.0f, 1.0f, gray(0.5f)});
  EXPECT_TRUE(arr.full());
  arr.push_back(Slab{5.0f, 1.0f, gray(0.5f)});
  ASSERT_EQ(arr.size(), 2);
  EXPECT_TRUE(near_slab(arr[0], Slab{1.0f, 1.0f, gray(0.5f)}, 0.0f));
  // last = last over extra, its back extended to the extra's back
  EXPECT_TRUE(near_slab(arr[1], Slab{5.0f, 4.0f, gray(0.75f)}, 1e-7f));
}

TEST(SlabArray, InsertInFrontOfAFullArrayFoldsTheTwoDeepest) {
  SlabArray<3> arr;
  arr.insert(Slab{2.0f, 1.0f, gray(0.5f)});
  arr.insert(Slab{4.0f, 1.0f, gray(0.5f)});
  arr.insert(Slab{6.0f, 1.0f, gray(0.5f)});
  arr.insert(Slab{0.5f, 0.5f, gray(0.2f)});
  ASSERT_EQ(arr.size(), 3);
  EXPECT_TRUE(near_slab(arr[0], Slab{0.5f, 0.5f, gray(0.2f)}, 0.0f));
  EXPECT_TRUE(near_slab(arr[1], Slab{2.0f, 1.0f, gray(0.5f)}, 0.0f));
  EXPECT_TRUE(near_slab(arr[2], Slab{6.0f, 3.0f, gray(0.75f)}, 1e-7f));
  // one slot, three slabs: everything folds into one slab in depth order
  SlabArray<1> one;
  one.insert(Slab{4.0f, 1.0f, {0, 0, 0.5f, 0.5f}});
  one.insert(Slab{2.0f, 1.0f, {0.5f, 0, 0, 0.5f}});
  one.insert(Slab{5.0f, 0.0f, {0, 0.5f, 0, 0.5f}});
  ASSERT_EQ(one.size(), 1);
  EXPECT_TRUE(near_slab(one[0], Slab{5.0f, 4.0f, {0.5f, 0.125f, 0.25f, 0.875f}}, 1e-7f));
}

TEST(GreedyMerge, CostIsZeroExactlyForEqualOpacityGradients) {
  // [0, 1] with A = 0.2 then [1, 2] with A = 0.25: both add 0.2 accumulated opacity per mm
  Slab a{1.0f, 1.0f, gray(0.2f)}, b{2.0f, 1.0f, gray(0.25f)};
  EXPECT_NEAR(merge_cost(a, b, 1.0f), 0.0f, 1e-7f);
  EXPECT_GT(merge_cost(a, Slab{2.0f, 1.0f, gray(0.9f)}, 1.0f), 0.1f);
  // a surface then a slab: the surface's opacity would be smeared over the merged slab
  EXPECT_NEAR(merge_cost(Slab{1.0f, 0.0f, gray(0.5f)}, Slab{2.0f, 1.0f, gray(0.5f)}, 1.0f), 0.5f,
              1e-7f);
  // coincident surfaces lose nothing; a hidden pair costs nothing
  EXPECT_EQ(merge_cost(Slab{1.0f, 0.0f, gray(0.5f)}, Slab{1.0f, 0.0f, gray(0.3f)}, 1.0f), 0.0f);
  EXPECT_EQ(merge_cost(a, Slab{2.0f, 1.0f, gray(0.9f)}, 0.0f), 0.0f);
  // a gap counts as empty medium
  EXPECT_GT(merge_cost(a, Slab{5.0f, 1.0f, gray(0.25f)}, 1.0f), 0.1f);
}

TEST(GreedyMerge, MergesThePairWithTheClosestGradients) {
  SlabArray<2> tail, greedy;
  std::vector<Slab> in = {
      {1.0f, 1.0f, gray(0.2f)}, {2.0f, 1.0f, gray(0.25f)}, {3.0f, 1.0f, gray(0.9f)}};
  for (const Slab& s : in) {
    tail.push_back(s, Overflow::tail);
    greedy.push_back(s, Overflow::greedy);
  }
  EXPECT_TRUE(near_slab(greedy[0], Slab{2.0f, 2.0f, gray(0.4f)}, 1e-6f));
  EXPECT_TRUE(near_slab(greedy[1], in[2], 0.0f));
  EXPECT_TRUE(near_slab(tail[0], in[0], 0.0f));
  EXPECT_TRUE(near_slab(tail[1], Slab{3.0f, 2.0f, gray(0.925f)}, 1e-6f));
  // the same choice when the new slab arrives in the middle by insert
  SlabArray<2> mid;
  mid.insert(in[0], Overflow::greedy);
  mid.insert(in[2], Overflow::greedy);
  mid.insert(in[1], Overflow::greedy);
  EXPECT_TRUE(near_slab(mid[0], greedy[0], 1e-6f));
  EXPECT_TRUE(near_slab(mid[1], greedy[1], 0.0f));
}

TEST(GreedyMerge, CompressReachesTheTarget) {
  SlabArray<8> arr;
  for (int i = 0; i < 8; ++i) arr.push_back(Slab{float(i + 1), 1.0f, gray(0.1f * float(i % 3))});
  glm::vec4 before = arr.accumulate(1.0f).color;
  arr.compress(3);
  EXPECT_EQ(arr.size(), 3);
  EXPECT_TRUE(is_sorted(arr.items()));
  EXPECT_TRUE(near4(arr.accumulate(1.0f).color, before, 1e-6f));
  EXPECT_EQ(arr[0].front(), 0.0f);
  EXPECT_EQ(arr[2].t_back, 8.0f);
  arr.compress(0);  // at least one slab is kept
  EXPECT_EQ(arr.size(), 1);
}

TEST(SlabArray, CapacityIsNeverExceededAndTheCompositeIsKept) {
  test::SlabRng rng(32);
  for (Overflow o : {Overflow::tail, Overflow::greedy})
    for (int trial = 0; trial < 200; ++trial) {
      SlabArray<4> arr, in_order;
      std::vector<Slab> all;
      int n = rng.integer(0, 20);
      for (int i = 0; i < n; ++i) {
        Slab s{rng.grid(0.0f, 20.0f), rng.grid(0.0f, 1.0f), rng.visibility()};
        all.push_back(s);
        arr.insert(s, o);
        ASSERT_LE(arr.size(), 4);
        ASSERT_EQ(arr.size(), std::min(i + 1, 4));
      }
      EXPECT_TRUE(is_sorted(arr.items()));
      std::vector<Slab> expect = sorted(all);
      float transmittance = 1.0f;
      for (const Slab& s : all) transmittance *= 1.0f - s.color.a;
      // folding multiplies transmittances whatever the arrival order
      EXPECT_NEAR(arr.accumulate(1.0f).color.a, 1.0f - transmittance, 2e-6f);
      if (!all.empty()) {
        EXPECT_EQ(arr[arr.size() - 1].t_back, expect.back().t_back);
      }
      // arriving in depth order, tail and greedy fold with associative over: nothing is lost
      for (const Slab& s : expect) in_order.push_back(s, o);
      EXPECT_TRUE(near4(in_order.accumulate(1.0f).color, accumulate(expect, 1.0f).color, 2e-6f));
    }
}

TEST(SlabList, BehavesLikeSlabArrayOverCallerStorage) {
  test::SlabRng rng(33);
  std::vector<Slab> storage(5);
  SlabList list(storage);
  SlabArray<5> arr;
  EXPECT_EQ(list.capacity(), 5);
  for (int i = 0; i < 30; ++i) {
    Slab s{rng.grid(0.0f, 20.0f), rng.grid(0.0f, 1.0f), rng.visibility()};
    list.insert(s, Overflow::greedy);
    arr.insert(s, Overflow::greedy);
  }
  ASSERT_EQ(list.size(), arr.size());
  for (int i = 0; i < list.size(); ++i) EXPECT_TRUE(near_slab(list[i], arr[i], 0.0f));
  EXPECT_EQ(storage[0].t_back, list[0].t_back);  // written through to the caller's storage
  SlabList resumed(storage, list.size());
  EXPECT_EQ(resumed.size(), 5);
  resumed.clear();
  EXPECT_TRUE(resumed.empty());
  std::vector<Slab> none;
  SlabList empty_list(none);
  empty_list.insert(Slab{1.0f, 1.0f, gray(1.0f)});  // no capacity: ignored, no overflow
  EXPECT_EQ(empty_list.size(), 0);
}

}  // namespace
}  // namespace imx
