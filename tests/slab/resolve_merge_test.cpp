#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "slab/accumulate.hpp"
#include "slab/resolve_merge.hpp"
#include "slab/sfm.hpp"
#include "slab_test_util.hpp"

namespace imx {
namespace {

using test::near4;
using test::near_slab;

std::vector<Slab> resolve(const std::vector<Slab>& in, int m, InSlabInterpolation interp = {}) {
  std::vector<Slab> out(size_t(std::max(m, 0)));
  out.resize(size_t(resolve_merge(in, out, interp)));
  return out;
}

// Fragments sorted by back depth, each of the same virtual thickness, so neighbours often overlap.
std::vector<Slab> fragments(test::SlabRng& rng, int n, float thickness) {
  std::vector<Slab> f;
  for (int i = 0; i < n; ++i) f.push_back(Slab{rng.grid(0.0f, 8.0f), thickness, rng.visibility()});
  std::sort(f.begin(), f.end(), [](const Slab& a, const Slab& b) { return a.t_back < b.t_back; });
  return f;
}

TEST(ResolveMerge, NeverEmitsMoreThanM) {
  test::SlabRng rng(51);
  for (int trial = 0; trial < 500; ++trial) {
    int n = rng.integer(0, 40), m = rng.integer(1, 8);
    std::vector<Slab> in = fragments(rng, n, rng.chance(0.5f) ? 0.25f : 0.0f);
    std::vector<Slab> out = resolve(in, m, {Interpolation::blend, rng.uniform(0.0f, 1.0f)});
    ASSERT_LE(int(out.size()), m);
    EXPECT_EQ(out.empty(), in.empty());
    for (size_t i = 1; i < out.size(); ++i) EXPECT_LE(out[i - 1].t_back, out[i].t_back);
    if (!in.empty()) {
      EXPECT_EQ(out.back().t_back, in.back().t_back);
    }
    // SFM and the tail both multiply transmittances: the total opacity is conserved
    float t = 1.0f;
    for (const Slab& s : in) t *= 1.0f - s.color.a;
    EXPECT_NEAR(accumulate(out, 1.0f).color.a, 1.0f - t, 2e-5f);
  }
}

TEST(ResolveMerge, WithoutOverlapsItIsPlainOver) {
  test::SlabRng rng(52);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<Slab> in = rng.disjoint_sequence(rng.integer(1, 12));
    int m = rng.integer(1, 14);
    std::vector<Slab> out = resolve(in, m);
    ASSERT_EQ(int(out.size()), std::min(m, int(in.size())));
    EXPECT_TRUE(near4(accumulate(out, 1.0f).color, accumulate(in, 1.0f).color, 1e-6f));
    // the first M - 1 fragments pass unchanged; the last slot holds the rest, folded by over
    int kept = int(in.size()) <= m ? int(in.size()) : m - 1;
    for (int i = 0; i < kept; ++i) EXPECT_TRUE(near_slab(out[i], in[i], 0.0f)) << i;
    if (int(in.size()) > m) {
      EXPECT_EQ(out.back().front(), in[m - 1].front());
      EXPECT_EQ(out.back().t_back, in.back().t_back);
    }
  }
}

TEST(ResolveMerge, OverlappingNeighboursMergeBySfm) {
  Slab a{2.0f, 2.0f, {0.5f, 0, 0, 0.5f}}, b{3.0f, 2.0f, {0, 0.5f, 0, 0.5f}};
  Slab c{6.0f, 1.0f, {0, 0, 0.5f, 0.5f}};
  std::vector<Slab> out = resolve({a, b, c}, 4);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(near_slab(out[0], sfm(a, b), 0.0f));
  EXPECT_TRUE(near_slab(out[1], c, 0.0f));
  // a chain of overlaps collapses into one slab
  Slab d{4.0f, 1.5f, {0.2f, 0.2f, 0.2f, 0.4f}};
  out = resolve({a, b, d}, 4);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(near_slab(out[0], sfm(sfm(a, b), d), 0.0f));
  EXPECT_EQ(out[0].front(), 0.0f);
  EXPECT_EQ(out[0].t_back, 4.0f);
  // only neighbours are compared: d overlaps the merged [0, 3] but c comes between them
  out = resolve({a, b, c, Slab{6.5f, 4.0f, {0.2f, 0.2f, 0.2f, 0.4f}}}, 4);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(near_slab(out[0], sfm(a, b), 0.0f));
}

TEST(ResolveMerge, CoplanarFragmentsBlendWhateverTheirOrder) {
  Slab red{4.0f, 0.1f, {0.9f, 0, 0, 0.9f}}, blue{4.0f, 0.1f, {0, 0, 0.9f, 0.9f}};
  std::vector<Slab> rb = resolve({red, blue}, 8), br = resolve({blue, red}, 8);
  ASSERT_EQ(rb.size(), 1u);
  ASSERT_EQ(br.size(), 1u);
  EXPECT_TRUE(near4(rb[0].color, br[0].color, 1e-7f));
  EXPECT_NEAR(rb[0].color.r, rb[0].color.b, 1e-7f);
}

TEST(ResolveMerge, EmptyInputOrNoSlots) {
  EXPECT_TRUE(resolve({}, 4).empty());
  EXPECT_TRUE(resolve({Slab{1.0f, 1.0f, {0.5f, 0, 0, 0.5f}}}, 0).empty());
}

}  // namespace
}  // namespace imx
