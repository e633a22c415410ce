#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "slab/mix.hpp"
#include "slab/ofm.hpp"
#include "slab_test_util.hpp"

namespace imx {
namespace {

using test::near4;

MergedFragment merge_all(const std::vector<Slab>& fragments) {
  MergedFragment acc = MergedFragment::from(fragments[0]);
  for (size_t i = 1; i < fragments.size(); ++i) acc = ofm_merge(acc, fragments[i]);
  return acc;
}

TEST(Ofm, TwoFragmentsHandValues) {
  Slab red{2.0f, 1.0f, {0.5f, 0, 0, 0.5f}}, green{2.5f, 1.0f, {0, 0.5f, 0, 0.5f}};
  MergedFragment m = ofm_merge(MergedFragment::from(red), green);
  EXPECT_TRUE(near4(m.slab.color, glm::vec4(0.375f, 0.375f, 0, 0.75f), 1e-7f));
  EXPECT_FLOAT_EQ(m.alpha_sum, 1.0f);
  EXPECT_EQ(m.slab.front(), 1.0f);  // the union of [1, 2] and [1.5, 2.5]
  EXPECT_EQ(m.slab.t_back, 2.5f);
}

TEST(Ofm, KeepsTheMediumColourNotThePremultipliedOne) {
  // three fragments: the incremental form must equal M1 over all of them
  std::vector<Slab> f = {{1.0f, 0.5f, {0.2f, 0, 0, 0.2f}},
                         {1.2f, 0.5f, {0, 0.4f, 0, 0.4f}},
                         {1.1f, 0.5f, {0, 0, 0.5f, 0.5f}}};
  MergedFragment m = merge_all(f);
  float s = 0.76f / 1.1f;
  EXPECT_TRUE(near4(m.slab.color, glm::vec4(0.2f * s, 0.4f * s, 0.5f * s, 0.76f), 1e-6f));
  EXPECT_FLOAT_EQ(m.alpha_sum, 1.1f);
  EXPECT_TRUE(near4(glm::vec4(m.medium_color() * 0.76f, 0.0f),
                    glm::vec4(glm::vec3(m.slab.color), 0.0f), 1e-6f));
}

TEST(Ofm, SameResultForEveryArrivalOrder) {
  test::SlabRng rng(21);
  for (int trial = 0; trial < 100; ++trial) {
    int n = rng.integer(2, 9);
    std::vector<Slab> f;
    for (int i = 0; i < n; ++i)  // all around depth 10, so they overlap one another
      f.push_back(
          Slab{10.0f + rng.uniform(-0.2f, 0.2f), rng.uniform(0.3f, 1.0f), rng.visibility()});
    MergedFragment first = merge_all(f);
    std::vector<glm::vec4> colours;
    for (const Slab& s : f) colours.push_back(s.color);
    EXPECT_TRUE(near4(first.slab.color, mix_m1(colours), 2e-6f));
    for (int perm = 0; perm < 30; ++perm) {
      std::shuffle(f.begin(), f.end(), rng.gen);
      MergedFragment m = merge_all(f);
      EXPECT_TRUE(near4(m.slab.color, first.slab.color, 2e-6f)) << "trial " << trial;
      EXPECT_NEAR(m.alpha_sum, first.alpha_sum, 1e-5f);
      EXPECT_EQ(m.slab.t_back, first.slab.t_back);
      EXPECT_NEAR(m.slab.front(), first.slab.front(), 1e-5f);
    }
  }
}

TEST(Ofm, MergingGroupsEqualsMergingOneByOne) {
  test::SlabRng rng(22);
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<Slab> f;
    for (int i = 0; i < 6; ++i) f.push_back(Slab{5.0f, 1.0f, rng.visibility()});
    MergedFragment left = merge_all({f[0], f[1], f[2]});
    MergedFragment right = merge_all({f[3], f[4], f[5]});
    EXPECT_TRUE(near4(ofm_merge(left, right).slab.color, merge_all(f).slab.color, 2e-6f));
  }
}

TEST(Ofm, TransparentFragmentsAreSafe) {
  Slab clear{1.0f, 0.5f, glm::vec4(0.0f)};
  MergedFragment m = ofm_merge(MergedFragment::from(clear), clear);
  EXPECT_EQ(m.slab.color, glm::vec4(0.0f));
  EXPECT_EQ(m.alpha_sum, 0.0f);
  Slab red{1.0f, 0.5f, {0.3f, 0, 0, 0.6f}};
  EXPECT_TRUE(near4(ofm_merge(m, red).slab.color, red.color, 1e-7f));
  EXPECT_TRUE(near4(ofm_merge(MergedFragment::from(red), clear).slab.color, red.color, 1e-7f));
}

}  // namespace
}  // namespace imx
