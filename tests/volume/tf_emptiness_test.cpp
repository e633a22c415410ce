#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "random_volumes.hpp"
#include "volume/tf_emptiness.hpp"
#include "volume/tf_lut.hpp"

namespace imx {
namespace {

TEST(TfEmptiness, AnswersForAPlateauTf) {
  TransferFunction tf;
  tf.points = {{0.0, {1, 1, 1, 0}},
               {100.0, {1, 1, 1, 0}},
               {110.0, {1, 1, 1, 1}},
               {200.0, {1, 1, 1, 1}},
               {210.0, {1, 1, 1, 0}}};
  TfLut lut(tf);
  TfEmptiness e(lut);
  EXPECT_TRUE(e.is_empty(-500.0f, 99.0f));  // below the first point the TF is constant 0
  EXPECT_TRUE(e.is_empty(212.0f, 1e9f));    // and above the last
  EXPECT_FALSE(e.is_empty(99.0f, 101.0f));
  EXPECT_FALSE(e.is_empty(150.0f, 150.0f));
  EXPECT_FALSE(e.is_empty(-1e9f, 1e9f));
  EXPECT_FALSE(e.is_empty(NAN, 10.0f));
  EXPECT_FALSE(e.is_empty(10.0f, 5.0f));
  TransferFunction clear;
  clear.points = {{0.0, {1, 0, 0, 0}}, {1.0, {0, 1, 0, 0}}};
  EXPECT_TRUE(TfEmptiness(TfLut(clear)).is_empty(-INFINITY, INFINITY));
}

// Conservative: a range reported empty has zero opacity at every value in it; and the query is not
// trivially "never empty".
TEST(TfEmptiness, NeverCallsAVisibleRangeEmpty) {
  std::mt19937 rng(5);
  int empties = 0;
  for (int trial = 0; trial < 40; ++trial) {
    TransferFunction tf = test::random_tf(rng, -100.0f, 300.0f);
    TfLut lut(tf);
    TfEmptiness e(lut);
    std::uniform_real_distribution<float> u(-150.0f, 350.0f), w(0.0f, 30.0f), near(-0.2f, 0.2f);
    std::uniform_int_distribution<int> point(0, static_cast<int>(tf.points.size()) - 1);
    for (int q = 0; q < 600; ++q) {
      float lo = u(rng), hi = lo + (q % 3 == 0 ? 0.0f : w(rng));
      if (q % 2) {  // ranges ending or starting within a LUT entry or two of a TF point
        float at = static_cast<float>(tf.points[point(rng)].value) + near(rng);
        if (q % 4 == 1)
          hi = at, lo = at - w(rng);
        else
          lo = at, hi = at + w(rng);
      }
      if (!e.is_empty(lo, hi)) continue;
      ++empties;
      for (int s = 0; s <= 400; ++s) {
        float v = lo + (hi - lo) * static_cast<float>(s) / 400.0f;
        ASSERT_EQ(lut.lookup(v).a, 0.0f) << v << " in [" << lo << ", " << hi << "]";
      }
    }
  }
  EXPECT_GT(empties, 1000);
}

// The visible part of a ramp: every value of the ramp outside [u0, u1] is transparent (checked
// densely), and the trim is tight: some value within one LUT entry inside each trimmed end is not.
// The marcher's fast test answers exactly as the table query on the sorted pair, for TFs with few
// transparent runs (value intervals) and with many (the table fallback), at values next to every
// LUT entry boundary, in either order, and for NaN and infinities.
TEST(TfEmptiness, FastPairTestEqualsTheTableQuery) {
  std::mt19937 rng(11);
  std::vector<TransferFunction> tfs;
  TransferFunction bands;  // transparent below 0, between the bands and above: 3 runs
  bands.points = {{0.0, {1, 1, 1, 0}},  {10.0, {1, 1, 1, 0.5f}}, {20.0, {1, 1, 1, 0}},
                  {40.0, {1, 1, 1, 0}}, {45.0, {1, 1, 1, 0.8f}}, {50.0, {1, 1, 1, 0}}};
  tfs.push_back(bands);
  TransferFunction comb;  // 7 transparent runs: beyond the intervals, the table answers
  for (int k = 0; k < 7; ++k) {
    comb.points.push_back({k * 10.0, {1, 1, 1, 0}});
    comb.points.push_back({k * 10.0 + 4.0, {1, 1, 1, 0}});
    comb.points.push_back({k * 10.0 + 6.0, {1, 1, 1, 0.6f}});
  }
  comb.points.push_back({80.0, {1, 1, 1, 0}});
  tfs.push_back(comb);
  for (int k = 0; k < 30; ++k) tfs.push_back(test::random_tf(rng, -100.0f, 300.0f));
  std::uniform_real_distribution<float> u(-150.0f, 350.0f);
  std::uniform_int_distribution<int> pick(0, 9);
  for (const TransferFunction& tf : tfs) {
    TfLut lut(tf);
    TfEmptiness e(lut);
    std::vector<float> values = {NAN, INFINITY, -INFINITY, 0.0f, -0.0f};
    for (int i = 0; i < TfLut::kSize; ++i) {  // at and beside every entry's value
      float edge = lut.lo() + (lut.hi() - lut.lo()) * static_cast<float>(i) / (TfLut::kSize - 1);
      values.insert(values.end(),
                    {std::nextafter(edge, -INFINITY), edge, std::nextafter(edge, INFINITY)});
    }
    for (int n = 0; n < 3000; ++n) {
      float a = pick(rng) == 0 ? values[rng() % values.size()] : u(rng);
      float b = pick(rng) == 0 ? values[rng() % values.size()] : u(rng);
      ASSERT_EQ(e.is_empty_between(a, b), e.is_empty(std::min(a, b), std::max(a, b)))
          << a << " " << b;
      if (!std::isnan(a) && !std::isnan(b)) {  // std::min/max favour a NaN's partner
        ASSERT_EQ(e.is_empty_between(a, b), e.is_empty_between(b, a)) << a << " " << b;
      }
    }
  }
}

TEST(TfEmptiness, VisiblePartTrimsOnlyTransparentEnds) {
  std::mt19937 rng(11);
  int trimmed = 0;
  for (int trial = 0; trial < 40; ++trial) {
    TransferFunction tf = test::random_tf(rng, -100.0f, 300.0f);
    TfLut lut(tf);
    TfEmptiness e(lut);
    const float entry = 1.0f / lut.inv_step();
    std::uniform_real_distribution<float> u(-150.0f, 350.0f);
    for (int q = 0; q < 300; ++q) {
      float s_f = u(rng), s_b = u(rng);
      if (e.is_empty(std::min(s_f, s_b), std::max(s_f, s_b))) continue;
      glm::vec2 part = e.visible_part(s_f, s_b);
      ASSERT_LE(0.0f, part.x);
      ASSERT_LE(part.x, part.y);
      ASSERT_LE(part.y, 1.0f);
      auto alpha_at = [&](float t) { return lut.lookup(s_f + t * (s_b - s_f)).a; };
      for (int k = 0; k <= 2000; ++k) {
        float t = static_cast<float>(k) / 2000.0f;
        if (t < part.x - 1e-4f || t > part.y + 1e-4f) {
          ASSERT_EQ(alpha_at(t), 0.0f) << t;
        }
      }
      // Tight: just inside a trimmed end (one LUT entry of the ramp) some opacity shows.
      float reach = entry / std::abs(s_b - s_f);
      auto visible_within = [&](float from, float to) {
        for (int k = 0; k <= 50; ++k)
          if (alpha_at(from + (to - from) * static_cast<float>(k) / 50.0f) > 0.0f) return true;
        return false;
      };
      if (part.x > 0.0f) {
        ++trimmed;
        EXPECT_TRUE(visible_within(part.x, std::min(part.y, part.x + reach)));
      }
      if (part.y < 1.0f) {
        EXPECT_TRUE(visible_within(std::max(part.x, part.y - reach), part.y));
      }
    }
  }
  EXPECT_GT(trimmed, 500);  // the random ramps must often start in transparent values
}

}  // namespace
}  // namespace imx
