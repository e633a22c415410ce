#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "slab/mix.hpp"
#include "slab/over.hpp"
#include "slab_test_util.hpp"

namespace imx {
namespace {

using test::near4;

TEST(Mix, PairwiseIsSymmetric) {
  test::SlabRng rng(3);
  for (int i = 0; i < 2000; ++i) {
    glm::vec4 a = rng.visibility(), b = rng.visibility();
    EXPECT_TRUE(near4(mix(a, b), mix(b, a), 1e-7f));
  }
}

TEST(Mix, PairwiseIsTheMeanOfBothOverOrders) {
  test::SlabRng rng(4);
  for (int i = 0; i < 2000; ++i) {
    glm::vec4 a = rng.visibility(), b = rng.visibility();
    EXPECT_TRUE(near4(mix(a, b), 0.5f * (over(a, b) + over(b, a)), 1e-6f));
  }
}

TEST(Mix, PairwiseHandValues) {
  // A = 1/3 + 1/4 - 1/12 = 1/2; C = C1 + C2 - (C1 A2 + C2 A1) / 2
  glm::vec4 a(1.0f / 3.0f, 0.0f, 0.0f, 1.0f / 3.0f), b(0.0f, 0.25f, 0.0f, 0.25f);
  EXPECT_TRUE(near4(mix(a, b), glm::vec4(7.0f / 24.0f, 5.0f / 24.0f, 0.0f, 0.5f), 1e-7f));
  // two opaque media of different colours blend half and half
  EXPECT_TRUE(
      near4(mix(glm::vec4(1, 0, 0, 1), glm::vec4(0, 0, 1, 1)), glm::vec4(0.5f, 0, 0.5f, 1), 0.0f));
}

TEST(Mix, EmptyIsTheIdentityAndZeroOpacityIsSafe) {
  test::SlabRng rng(5);
  for (int i = 0; i < 200; ++i) {
    glm::vec4 a = rng.visibility();
    EXPECT_TRUE(near4(mix(a, glm::vec4(0.0f)), a, 0.0f));
    EXPECT_TRUE(near4(mix(glm::vec4(0.0f), a), a, 0.0f));
  }
  // purely emissive (A = 0) contributions add
  EXPECT_TRUE(near4(mix(glm::vec4(0.1f, 0, 0, 0), glm::vec4(0, 0.2f, 0, 0)),
                    glm::vec4(0.1f, 0.2f, 0, 0), 0.0f));
}

TEST(Mix, SlabsKeepTheirCommonInterval) {
  Slab a{4.0f, 2.0f, glm::vec4(0.5f, 0, 0, 0.5f)}, b{4.0f, 2.0f, glm::vec4(0, 0.5f, 0, 0.5f)};
  Slab m = mix(a, b);
  EXPECT_EQ(m.t_back, 4.0f);
  EXPECT_EQ(m.thickness, 2.0f);
  EXPECT_TRUE(near4(m.color, mix(a.color, b.color), 0.0f));
}

TEST(MixM1, HandValues) {
  std::vector<glm::vec4> v = {{0.5f, 0, 0, 0.5f}, {0, 0.5f, 0, 0.5f}};
  // A = 1 - 0.25, c = (0.5, 0.5, 0) / 1, C = c A
  EXPECT_TRUE(near4(mix_m1(v), glm::vec4(0.375f, 0.375f, 0, 0.75f), 1e-7f));
  std::vector<glm::vec4> three = {{0.2f, 0, 0, 0.2f}, {0, 0.4f, 0, 0.4f}, {0, 0, 0.5f, 0.5f}};
  // A = 1 - 0.8 * 0.6 * 0.5 = 0.76; sum A = 1.1
  float s = 0.76f / 1.1f;
  EXPECT_TRUE(near4(mix_m1(three), glm::vec4(0.2f * s, 0.4f * s, 0.5f * s, 0.76f), 1e-6f));
}

TEST(MixM1, IndependentOfOrderForAnyPermutation) {
  test::SlabRng rng(6);
  for (int n = 1; n <= 8; ++n)
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<glm::vec4> v;
      for (int i = 0; i < n; ++i) v.push_back(rng.visibility());
      glm::vec4 first = mix_m1(v);
      for (int perm = 0; perm < 30; ++perm) {
        std::shuffle(v.begin(), v.end(), rng.gen);
        EXPECT_TRUE(near4(mix_m1(v), first, 2e-6f)) << "n " << n;
      }
    }
}

TEST(MixM1, OneInputIsReturnedAndOpacityMatchesPairwise) {
  test::SlabRng rng(8);
  for (int i = 0; i < 200; ++i) {
    glm::vec4 a = rng.visibility(), b = rng.visibility();
    EXPECT_TRUE(near4(mix_m1(std::vector<glm::vec4>{a}), a, 1e-6f));
    EXPECT_NEAR(mix_m1(std::vector<glm::vec4>{a, b}).a, mix(a, b).a, 1e-6f);
  }
}

TEST(MixM1, ZeroOpacityIsSafe) {
  std::vector<glm::vec4> none = {glm::vec4(0.0f), glm::vec4(0.0f)};
  EXPECT_EQ(mix_m1(none), glm::vec4(0.0f));
  EXPECT_EQ(mix_m1(std::vector<glm::vec4>{}), glm::vec4(0.0f));
  std::vector<glm::vec4> some = {glm::vec4(0.0f), {0.3f, 0, 0, 0.6f}};
  EXPECT_TRUE(near4(mix_m1(some), glm::vec4(0.3f, 0, 0, 0.6f), 1e-7f));
}

TEST(MixM1, SlabsCoverTheUnionOfTheirIntervals) {
  std::vector<Slab> s = {{3.0f, 1.0f, glm::vec4(0.5f, 0, 0, 0.5f)},
                         {4.0f, 1.5f, glm::vec4(0, 0.5f, 0, 0.5f)}};
  Slab m = mix_m1(s);
  EXPECT_EQ(m.t_back, 4.0f);
  EXPECT_EQ(m.front(), 2.0f);
  EXPECT_TRUE(near4(m.color, glm::vec4(0.375f, 0.375f, 0, 0.75f), 1e-7f));
  EXPECT_TRUE(mix_m1(std::span<const Slab>()).is_empty());
}

TEST(MixExclusive, TheFirstInPriorityAboveTheThresholdWinsAlone) {
  const std::vector<glm::vec4> v = {{0.1f, 0, 0, 0.2f}, {0, 0.3f, 0, 0.6f}, {0, 0, 0.4f, 0.8f}};
  const std::vector<float> none(3, 0.0f);
  // Priority order 2, 0, 1: the third wins.
  EXPECT_TRUE(near4(mix_exclusive(v, std::vector<uint8_t>{1, 2, 0}, none), v[2], 1e-7f));
  EXPECT_TRUE(near4(mix_exclusive(v, std::vector<uint8_t>{0, 1, 2}, none), v[0], 1e-7f));
  // A threshold the first does not pass hands the win to the next.
  EXPECT_TRUE(
      near4(mix_exclusive(v, std::vector<uint8_t>{0, 1, 2}, std::vector<float>{0.5f, 0.5f, 0.5f}),
            v[1], 1e-7f));
}

TEST(MixExclusive, WhenNoneExceedsTheThresholdTheLastPresentWins) {
  const std::vector<glm::vec4> v = {{0.1f, 0, 0, 0.2f}, {0, 0.1f, 0, 0.3f}, glm::vec4(0.0f)};
  const std::vector<float> high(3, 0.9f);
  // Rank 2 has no opacity: it is not present, so rank 1 is the last present one.
  EXPECT_TRUE(near4(mix_exclusive(v, std::vector<uint8_t>{0, 1, 2}, high), v[1], 1e-7f));
  EXPECT_TRUE(near4(mix_exclusive(std::vector<glm::vec4>(2, glm::vec4(0.0f)),
                                  std::vector<uint8_t>{0, 1}, std::vector<float>(2, 0.0f)),
                    glm::vec4(0.0f), 1e-7f));
}

TEST(MixExclusive, AGroupIsMixedInclusively) {
  const std::vector<glm::vec4> v = {{0.2f, 0, 0, 0.4f}, {0, 0.25f, 0, 0.5f}, {0, 0, 0.9f, 0.9f}};
  const std::vector<glm::vec4> group = {v[0], v[1]};
  EXPECT_TRUE(near4(mix_exclusive(v, std::vector<uint8_t>{0, 0, 1}, std::vector<float>(3, 0.0f)),
                    mix_m1(group), 1e-7f));
}

}  // namespace
}  // namespace imx
