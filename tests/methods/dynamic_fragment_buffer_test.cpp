#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "methods/fragment/dynamic_fragment_buffer.hpp"

namespace imx {
namespace {

std::vector<Fragment> random_fragments(std::mt19937& gen, int n) {
  std::uniform_int_distribution<int> depth(0, n / 2 + 1), object(0, 5);
  std::vector<Fragment> f(n);
  for (Fragment& x : f) {
    x.t = 10.0f + 0.5f * depth(gen);  // repeated depths: ties are common
    x.object = uint32_t(object(gen));
  }
  return f;
}

TEST(DynamicFragmentBuffer, SortsByDepthThenSceneOrderOnBothSortPaths) {
  std::mt19937 gen(3);
  for (int n : {0, 1, 2, 5, 15, 16, 17, 40, 300}) {
    std::vector<Fragment> f = random_fragments(gen, n);
    std::vector<Fragment> expected = f;
    std::stable_sort(expected.begin(), expected.end(), fragment_before);
    std::span<Fragment> sorted = dfb_sort(f);
    ASSERT_EQ(sorted.size(), size_t(n));
    for (int i = 0; i < n; ++i) {
      EXPECT_EQ(sorted[i].t, expected[i].t) << "n " << n << " i " << i;
      EXPECT_EQ(sorted[i].object, expected[i].object) << "n " << n << " i " << i;
    }
  }
}

TEST(DynamicFragmentBuffer, ResultDoesNotDependOnArrivalOrder) {
  std::mt19937 gen(5);
  std::vector<Fragment> f = random_fragments(gen, 24);
  for (Fragment& x : f) x.object = uint32_t(&x - f.data());  // distinct keys
  std::vector<Fragment> first = f;
  dfb_sort(first);
  for (int trial = 0; trial < 20; ++trial) {
    std::shuffle(f.begin(), f.end(), gen);
    std::vector<Fragment> g = f;
    dfb_sort(g);
    for (size_t i = 0; i < g.size(); ++i) EXPECT_EQ(g[i].object, first[i].object);
  }
}

TEST(DynamicFragmentBuffer, CapKeepsTheFirstArrivals) {
  std::vector<Fragment> f(10);
  for (int i = 0; i < 10; ++i) f[i].t = float(10 - i);  // arrive back to front
  std::span<Fragment> kept = dfb_sort(f, 4);
  ASSERT_EQ(kept.size(), 4u);
  EXPECT_EQ(kept[0].t, 7.0f);  // the store pass had room for depths 10, 9, 8, 7 only
  EXPECT_EQ(kept[3].t, 10.0f);
  EXPECT_EQ(dfb_sort(f, 0).size(), 0u);
}

}  // namespace
}  // namespace imx
