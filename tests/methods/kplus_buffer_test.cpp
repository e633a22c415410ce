#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "../slab/slab_test_util.hpp"
#include "methods/fragment/kplus_buffer.hpp"
#include "slab/mix.hpp"

namespace imx {
namespace {

using test::near4;

glm::vec4 colour(float r, float g, float b, float a) {
  return {r * a, g * a, b * a, a};
}

glm::vec4 sorted_over(std::vector<Slab> s) {
  std::stable_sort(s.begin(), s.end(),
                   [](const Slab& a, const Slab& b) { return a.t_back < b.t_back; });
  glm::vec4 c(0.0f);
  for (const Slab& x : s) c = over(c, x.color);
  return c;
}

glm::vec4 fill(const KPlusSettings& k, const std::vector<Slab>& arrival) {
  KPlusBuffer b(k);
  for (const Slab& s : arrival) b.insert(s);
  return b.composite();
}

TEST(KPlusBuffer, WithRoomForAllIsExactOverForEveryArrivalOrder) {
  std::mt19937 gen(1);
  std::vector<Slab> f;
  for (int i = 0; i < 6; ++i)
    f.push_back(Slab{10.0f + 3.0f * i, 0.0f, colour(0.1f * i, 0.5f, 1.0f - 0.1f * i, 0.3f)});
  glm::vec4 exact = sorted_over(f);
  for (int trial = 0; trial < 30; ++trial) {
    std::shuffle(f.begin(), f.end(), gen);
    EXPECT_TRUE(near4(fill({8, false}, f), exact, 1e-6f));
    EXPECT_TRUE(near4(fill({6, true}, f), exact, 1e-6f));
  }
}

TEST(KPlusBuffer, KeepsTheKNearestAndMixesTheRestIntoTheTail) {
  std::mt19937 gen(2);
  std::vector<Slab> f;
  for (int i = 0; i < 12; ++i)
    f.push_back(
        Slab{float(i + 1), 0.0f, colour(i % 3 == 0, i % 3 == 1, i % 3 == 2, 0.2f + 0.05f * i)});
  for (int trial = 0; trial < 20; ++trial) {
    std::shuffle(f.begin(), f.end(), gen);
    KPlusBuffer b({4, false});
    for (const Slab& s : f) b.insert(s);
    ASSERT_EQ(b.size(), 4);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(b.stored()[i].slab.t_back, float(i + 1));
    ASSERT_TRUE(b.has_tail());
    std::vector<glm::vec4> rest;
    std::vector<Slab> sorted = f;
    std::sort(sorted.begin(), sorted.end(),
              [](const Slab& a, const Slab& c) { return a.t_back < c.t_back; });
    for (int i = 4; i < 12; ++i) rest.push_back(sorted[i].color);
    EXPECT_TRUE(near4(b.tail().slab.color, mix_m1(rest), 2e-6f));  // the same for any order
    EXPECT_EQ(b.tail().slab.front(), 5.0f);
    EXPECT_EQ(b.tail().slab.t_back, 12.0f);
    Slab out[kMaxKBufferSize + 1];
    EXPECT_EQ(b.resolve(out), 5);
  }
}

TEST(KPlusBuffer, TotalOpacityIsKeptWhateverOverflows) {
  std::mt19937 gen(4);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Slab> f;
    float transmittance = 1.0f;
    for (int i = 0; i < 20; ++i) {
      float a = u(gen) * 0.6f;
      f.push_back(
          Slab{20.0f * u(gen), u(gen) < 0.5f ? 0.0f : 0.5f, colour(u(gen), u(gen), u(gen), a)});
      transmittance *= 1.0f - a;
    }
    for (bool merge : {false, true}) {
      glm::vec4 c = fill({4, merge}, f);
      EXPECT_NEAR(c.a, 1.0f - transmittance, 1e-5f);
    }
  }
}

TEST(KPlusBuffer, OfmMergesCoplanarFragmentsTheSameForEveryArrivalOrder) {
  // three pairs of coplanar fragments and two loners; with OFM they take five of six slots
  std::vector<Slab> f = {
      {10.0f, 0.5f, colour(1, 0, 0, 0.5f)},  {10.0f, 0.5f, colour(0, 1, 0, 0.6f)},
      {14.0f, 0.5f, colour(0, 0, 1, 0.3f)},  {14.0f, 0.5f, colour(1, 1, 0, 0.4f)},
      {18.0f, 0.5f, colour(0, 1, 1, 0.7f)},  {18.0f, 0.5f, colour(1, 0, 1, 0.2f)},
      {12.0f, 0.5f, colour(1, 1, 1, 0.25f)}, {16.0f, 0.5f, colour(.5f, .5f, .5f, 0.35f)}};
  std::vector<int> order(f.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = int(i);
  std::vector<Slab> arrival(f.size());
  glm::vec4 first(-1.0f);
  int permutations = 0;
  do {
    for (size_t i = 0; i < order.size(); ++i) arrival[i] = f[order[i]];
    KPlusBuffer b({6, true});
    for (const Slab& s : arrival) b.insert(s);
    EXPECT_EQ(b.size(), 5);
    EXPECT_FALSE(b.has_tail());
    if (permutations++ == 0) first = b.composite();
    EXPECT_TRUE(near4(b.composite(), first, 2e-6f));
  } while (std::next_permutation(order.begin(), order.end()));
  EXPECT_EQ(permutations, 40320);
  // the coplanar pair in front merges by M1
  std::vector<glm::vec4> pair = {f[0].color, f[1].color};
  KPlusBuffer b({6, true});
  b.insert(f[1]);
  b.insert(f[0]);
  EXPECT_TRUE(near4(b.stored()[0].slab.color, mix_m1(pair), 1e-6f));
}

TEST(KPlusBuffer, OfmChainsMergesThatWidenAFragment) {
  KPlusBuffer b({4, true});
  b.insert(Slab{10.0f, 1.0f, colour(1, 0, 0, 0.2f)});  // [9, 10]
  b.insert(Slab{12.0f, 1.0f, colour(0, 1, 0, 0.2f)});  // [11, 12]
  b.insert(Slab{11.5f, 2.0f, colour(0, 0, 1, 0.2f)});  // [9.5, 11.5] bridges both
  ASSERT_EQ(b.size(), 1);
  EXPECT_EQ(b.stored()[0].slab.front(), 9.0f);
  EXPECT_EQ(b.stored()[0].slab.t_back, 12.0f);
}

TEST(KPlusBuffer, BytesPerPixel) {
  EXPECT_EQ(KPlusBuffer::bytes_per_pixel(8, false), 9 * 20);
  EXPECT_EQ(KPlusBuffer::bytes_per_pixel(8, true), 9 * 28);
}

}  // namespace
}  // namespace imx
