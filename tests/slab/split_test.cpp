#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "slab/over.hpp"
#include "slab/split.hpp"
#include "slab_test_util.hpp"

namespace imx {
namespace {

using test::near4;

const std::vector<InSlabInterpolation> kModes = {
    {Interpolation::ovi, 1.0f},    {Interpolation::hvi, 0.0f},   {Interpolation::blend, 0.0f},
    {Interpolation::blend, 0.25f}, {Interpolation::blend, 0.5f}, {Interpolation::blend, 0.9f},
    {Interpolation::blend, 1.0f}};

const std::vector<float> kOpacities = {0.0f,  1e-6f,  0.01f,   0.3f, 0.5f,
                                       0.75f, 0.999f, 0.9999f, 1.0f};
const std::vector<float> kFractions = {0.0f, 1e-4f, 0.1f, 0.25f, 0.5f, 0.9f, 0.9999f, 1.0f};

glm::vec4 rgba(float r, float g, float b, float a) {
  return {r, g, b, a};
}

void expect_recomposes(const Slab& s, float t, const InSlabInterpolation& m) {
  SlabParts parts = split(s, t, m);
  EXPECT_TRUE(near4(over(parts.front.color, parts.back.color), s.color, 1e-6f))
      << "mode " << int(m.mode) << " beta " << m.beta << " A " << s.color.a << " t " << t;
  // depths are stored as (back, thickness): fronts are exact up to rounding
  EXPECT_NEAR(parts.front.front(), s.front(), 1e-4f);
  EXPECT_NEAR(parts.front.t_back, parts.back.front(), 1e-4f);
  EXPECT_EQ(parts.back.t_back, s.t_back);
  EXPECT_NEAR(parts.front.thickness + parts.back.thickness, s.thickness, 1e-4f);
  EXPECT_GE(parts.front.color.a, 0.0f);
  EXPECT_LE(parts.front.color.a, 1.0f);
  EXPECT_GE(parts.back.color.a, 0.0f);
  EXPECT_LE(parts.back.color.a, 1.0f);
}

TEST(Split, RecomposesExactlyForEveryModeOpacityAndDepth) {
  for (const auto& m : kModes)
    for (float a : kOpacities)
      for (float x : kFractions) {
        Slab s{5.0f, 2.0f, rgba(0.2f * a, 0.7f * a, a, a)};
        expect_recomposes(s, x * s.thickness, m);
      }
}

TEST(Split, RecomposesRandomSlabsAndDepths) {
  test::SlabRng rng(7);
  for (int i = 0; i < 5000; ++i) {
    InSlabInterpolation m{Interpolation(rng.integer(0, 2)), rng.uniform(0.0f, 1.0f)};
    Slab s{rng.uniform(-50.0f, 50.0f), rng.uniform(0.0f, 20.0f), rng.visibility()};
    expect_recomposes(s, rng.uniform(-1.0f, 1.2f) * s.thickness, m);
  }
}

TEST(Split, OviIsLinearInDepth) {
  Slab s{4.0f, 4.0f, rgba(0.4f, 0.2f, 0.0f, 0.8f)};
  SlabParts p = split(s, 1.0f, {Interpolation::ovi});
  EXPECT_TRUE(near4(p.front.color, rgba(0.1f, 0.05f, 0.0f, 0.2f), 1e-7f));
  // back = (whole - front) / (1 - A_f) = (0.3, 0.15, 0, 0.6) / 0.8
  EXPECT_TRUE(near4(p.back.color, rgba(0.375f, 0.1875f, 0.0f, 0.75f), 1e-6f));
  EXPECT_FLOAT_EQ(p.front.t_back, 1.0f);
  EXPECT_FLOAT_EQ(p.front.thickness, 1.0f);
  EXPECT_FLOAT_EQ(p.back.thickness, 3.0f);
}

TEST(Split, HviFollowsTheHomogeneousMediumOnBothSides) {
  for (float a : {0.01f, 0.3f, 0.75f, 0.99f})
    for (float x : {0.1f, 0.5f, 0.8f}) {
      Slab s{10.0f, 10.0f, rgba(0.5f * a, 0.0f, a, a)};
      SlabParts p = split(s, 10.0f * x, {Interpolation::hvi});
      double af = 1.0 - std::pow(1.0 - a, double(x));
      double ab = 1.0 - std::pow(1.0 - a, 1.0 - double(x));  // the same formula with d - t
      EXPECT_NEAR(p.front.color.a, af, 1e-6);
      EXPECT_NEAR(p.back.color.a, ab, 1e-5);
      // colour scales with opacity: C_f = C A_f / A, so the medium colour is unchanged
      EXPECT_NEAR(p.front.color.r / p.front.color.a, 0.5, 1e-5);
      EXPECT_NEAR(p.back.color.b / p.back.color.a, 1.0, 1e-5);
    }
}

TEST(Split, HviHalvesOfThreeQuartersAreOneHalfEach) {
  Slab s{2.0f, 2.0f, rgba(0.75f, 0.0f, 0.0f, 0.75f)};
  SlabParts p = split_at_depth(s, 1.0f, {Interpolation::hvi});
  EXPECT_TRUE(near4(p.front.color, rgba(0.5f, 0.0f, 0.0f, 0.5f), 1e-6f));
  EXPECT_TRUE(near4(p.back.color, rgba(0.5f, 0.0f, 0.0f, 0.5f), 1e-6f));
}

TEST(Split, BlendEndpointsAreOviAndHvi) {
  test::SlabRng rng(11);
  for (int i = 0; i < 500; ++i) {
    Slab s{rng.uniform(1.0f, 5.0f), 1.0f, rng.visibility()};
    float t = rng.uniform(0.0f, 1.0f);
    auto ovi = split(s, t, {Interpolation::ovi});
    auto hvi = split(s, t, {Interpolation::hvi});
    auto b1 = split(s, t, {Interpolation::blend, 1.0f});
    auto b0 = split(s, t, {Interpolation::blend, 0.0f});
    EXPECT_TRUE(near4(b1.front.color, ovi.front.color, 1e-7f));
    EXPECT_TRUE(near4(b1.back.color, ovi.back.color, 1e-6f));
    EXPECT_TRUE(near4(b0.front.color, hvi.front.color, 1e-7f));
    EXPECT_TRUE(near4(b0.back.color, hvi.back.color, 1e-6f));
    // in between, the front opacity is the beta-weighted mean of the two (seed 002 eq. 4)
    auto bh = split(s, t, {Interpolation::blend, 0.3f});
    EXPECT_NEAR(bh.front.color.a, 0.3f * ovi.front.color.a + 0.7f * hvi.front.color.a, 1e-6f);
  }
}

TEST(Split, FrontOpacityGrowsWithDepth) {
  for (const auto& m : kModes)
    for (float a : kOpacities) {
      float last = 0.0f;
      for (int k = 0; k <= 100; ++k) {
        float af = front_visibility(rgba(a, a, a, a), k / 100.0f, m).a;
        EXPECT_GE(af, last - 1e-7f);
        EXPECT_LE(af, a + 1e-7f);
        last = af;
      }
      EXPECT_NEAR(last, a, 1e-6f);
    }
}

TEST(Split, OpaqueSlabBackPartIsDefined) {
  const glm::vec4 red(1.0f, 0.0f, 0.0f, 1.0f);
  Slab s{3.0f, 3.0f, red};
  // OVI: the front holds t/d of the opacity, the opaque rest is all in the back
  SlabParts ovi = split(s, 1.0f, {Interpolation::ovi});
  EXPECT_TRUE(near4(ovi.front.color, red / 3.0f, 1e-7f));
  EXPECT_TRUE(near4(ovi.back.color, red, 1e-6f));
  // HVI: any depth into an opaque medium is opaque; the back part is hidden and left empty
  SlabParts hvi = split(s, 1.0f, {Interpolation::hvi});
  EXPECT_EQ(hvi.front.color, red);
  EXPECT_EQ(hvi.back.color, glm::vec4(0.0f));
  // OVI at the very back: the front is the whole slab, the back empty (the A_f -> 1 guard)
  SlabParts end = split(s, 3.0f, {Interpolation::ovi});
  EXPECT_EQ(end.front.color, red);
  EXPECT_EQ(end.back.color, glm::vec4(0.0f));
  for (const auto& m : kModes)
    for (float x : kFractions) {
      SlabParts p = split(s, 3.0f * x, m);
      EXPECT_TRUE(near4(over(p.front.color, p.back.color), red, 1e-6f));
      EXPECT_TRUE(std::isfinite(p.back.color.r) && std::isfinite(p.back.color.a));
    }
}

TEST(Split, TransparentSlabStaysFinite) {
  for (const auto& m : kModes) {
    SlabParts p = split(Slab{1.0f, 1.0f, glm::vec4(0.0f)}, 0.5f, m);
    EXPECT_EQ(p.front.color, glm::vec4(0.0f));
    EXPECT_EQ(p.back.color, glm::vec4(0.0f));
  }
}

TEST(Split, EndsGiveTheWholeSlabToOneSide) {
  Slab s{7.0f, 2.0f, rgba(0.1f, 0.2f, 0.3f, 0.4f)};
  for (const auto& m : kModes) {
    SlabParts at0 = split(s, 0.0f, m);
    EXPECT_EQ(at0.front.color, glm::vec4(0.0f));
    EXPECT_EQ(at0.front.thickness, 0.0f);
    EXPECT_EQ(at0.front.t_back, 5.0f);
    EXPECT_EQ(at0.back.color, s.color);
    EXPECT_EQ(at0.back.thickness, 2.0f);
    SlabParts atd = split(s, 2.0f, m);
    EXPECT_EQ(atd.front.color, s.color);
    EXPECT_EQ(atd.front.t_back, 7.0f);
    EXPECT_EQ(atd.back.color, glm::vec4(0.0f));
    EXPECT_EQ(atd.back.thickness, 0.0f);
    // outside the slab, by depth
    EXPECT_EQ(split_at_depth(s, 4.0f, m).back.color, s.color);
    EXPECT_EQ(split_at_depth(s, 9.0f, m).front.color, s.color);
  }
}

TEST(Split, SurfaceGoesWholeIntoTheFrontPart) {
  Slab surface{3.0f, 0.0f, rgba(0.0f, 0.5f, 0.0f, 0.5f)};
  for (const auto& m : kModes) {
    SlabParts p = split(surface, 0.0f, m);
    EXPECT_EQ(p.front.color, surface.color);
    EXPECT_EQ(p.front.t_back, 3.0f);
    EXPECT_EQ(p.back.color, glm::vec4(0.0f));
    EXPECT_EQ(p.back.thickness, 0.0f);
    EXPECT_EQ(split_at_depth(surface, 3.0f, m).front.color, surface.color);
    EXPECT_EQ(split_at_depth(surface, 2.0f, m).back.color, surface.color);
  }
}

TEST(Split, AtDepthMeetsExactlyAtTheCut) {
  Slab s{0.3f, 0.7f, rgba(0.1f, 0.1f, 0.1f, 0.2f)};
  SlabParts p = split_at_depth(s, 0.1f, {});
  EXPECT_EQ(p.front.t_back, 0.1f);
  EXPECT_FLOAT_EQ(p.back.front(), 0.1f);
  EXPECT_EQ(p.back.t_back, 0.3f);
}

}  // namespace
}  // namespace imx
