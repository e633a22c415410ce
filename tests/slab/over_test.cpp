#include <gtest/gtest.h>

#include <vector>

#include "slab/accumulate.hpp"
#include "slab/over.hpp"
#include "slab_test_util.hpp"

namespace imx {
namespace {

using test::near4;

TEST(Over, PremultipliedHandValues) {
  glm::vec4 front(0.5f, 0, 0, 0.5f), back(0, 0.8f, 0, 0.8f);
  EXPECT_TRUE(near4(over(front, back), glm::vec4(0.5f, 0.4f, 0, 0.9f), 1e-7f));
  EXPECT_TRUE(near4(over(glm::vec4(0.0f), back), back, 0.0f));
  EXPECT_TRUE(near4(over(front, glm::vec4(0.0f)), front, 0.0f));
  EXPECT_TRUE(near4(over(glm::vec4(0, 0, 1, 1), back), glm::vec4(0, 0, 1, 1), 0.0f));
}

TEST(Over, IsAssociative) {
  test::SlabRng rng(1);
  for (int i = 0; i < 1000; ++i) {
    glm::vec4 a = rng.visibility(), b = rng.visibility(), c = rng.visibility();
    EXPECT_TRUE(near4(over(over(a, b), c), over(a, over(b, c)), 1e-6f));
  }
}

TEST(Over, SlabsSpanBothIntervals) {
  Slab front{2.0f, 1.0f, {0.5f, 0, 0, 0.5f}}, back{5.0f, 0.5f, {0, 0.8f, 0, 0.8f}};
  Slab s = over(front, back);
  EXPECT_EQ(s.front(), 1.0f);
  EXPECT_EQ(s.t_back, 5.0f);
  EXPECT_TRUE(near4(s.color, glm::vec4(0.5f, 0.4f, 0, 0.9f), 1e-7f));
  Slab surface{3.0f, 0.0f, {0, 0, 0.2f, 0.2f}};
  Slab t = over(surface, surface);
  EXPECT_EQ(t.thickness, 0.0f);
  EXPECT_EQ(t.t_back, 3.0f);
}

TEST(Overlaps, IntervalCases) {
  Slab a{2.0f, 1.0f, {}};                           // [1, 2]
  EXPECT_TRUE(overlaps(a, Slab{2.5f, 1.0f, {}}));   // partial
  EXPECT_TRUE(overlaps(a, Slab{1.8f, 0.5f, {}}));   // contained
  EXPECT_TRUE(overlaps(a, Slab{2.0f, 1.0f, {}}));   // aligned
  EXPECT_FALSE(overlaps(a, Slab{3.0f, 1.0f, {}}));  // touching behind
  EXPECT_FALSE(overlaps(a, Slab{1.0f, 0.5f, {}}));  // touching in front
  EXPECT_FALSE(overlaps(a, Slab{4.0f, 1.0f, {}}));  // apart
  EXPECT_TRUE(overlaps(a, Slab{1.5f, 0.0f, {}}));   // a surface inside
  EXPECT_TRUE(overlaps(Slab{1.5f, 0.0f, {}}, a));   // either way round
  EXPECT_FALSE(overlaps(a, Slab{2.0f, 0.0f, {}}));  // a surface on the back boundary
  EXPECT_FALSE(overlaps(a, Slab{1.0f, 0.0f, {}}));  // a surface on the front boundary
  EXPECT_TRUE(overlaps(Slab{1.0f, 0.0f, {}}, Slab{1.0f, 0.0f, {}}));   // coplanar surfaces
  EXPECT_FALSE(overlaps(Slab{1.0f, 0.0f, {}}, Slab{1.5f, 0.0f, {}}));  // distinct surfaces
}

TEST(Accumulate, CompositesFrontToBack) {
  std::vector<Slab> s = {{1.0f, 1.0f, {0.5f, 0, 0, 0.5f}}, {2.0f, 1.0f, {0, 0.8f, 0, 0.8f}}};
  Accumulation r = accumulate(s, 1.0f);
  EXPECT_TRUE(near4(r.color, glm::vec4(0.5f, 0.4f, 0, 0.9f), 1e-7f));
  EXPECT_EQ(r.used, 2);
  EXPECT_FALSE(r.terminated);
}

TEST(Accumulate, EarlyRayTerminationStopsAtTheThreshold) {
  std::vector<Slab> s;
  for (int i = 0; i < 10; ++i) s.push_back(Slab{float(i + 1), 1.0f, {0.5f, 0, 0, 0.5f}});
  // opacity after k slabs: 1 - 2^-k; 0.9 is first reached with k = 4 (0.9375)
  Accumulation r = accumulate(s, 0.9f);
  EXPECT_TRUE(r.terminated);
  EXPECT_EQ(r.used, 4);
  EXPECT_FLOAT_EQ(r.color.a, 0.9375f);
  // 1 disables ERT, even when the accumulated opacity reaches 1
  std::vector<Slab> opaque = {{1.0f, 1.0f, {1, 0, 0, 1}}, {2.0f, 1.0f, {0, 1, 0, 1}}};
  Accumulation all = accumulate(opaque, 1.0f);
  EXPECT_FALSE(all.terminated);
  EXPECT_EQ(all.used, 2);
  Accumulation stop = accumulate(opaque);  // default 0.99
  EXPECT_TRUE(stop.terminated);
  EXPECT_EQ(stop.used, 1);
  EXPECT_EQ(accumulate(std::span<const Slab>()).used, 0);
}

}  // namespace
}  // namespace imx
