// The per-sample label classifier: the winner is a label of the eight voxels around the sample
// with the largest interpolated indicator, so a boundary shows only the labels on either side.
#include <map>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "volume/label_classifier.hpp"

namespace imx {
namespace {

// The winner computed independently: each corner's trilinear weight in double, summed per label.
int32_t expected_winner(const std::vector<uint16_t>& v, glm::ivec3 d, glm::dvec3 p) {
  const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(p)), d - 2);
  const glm::dvec3 f = p - glm::dvec3(i0);
  std::map<int32_t, double> sum;
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 o(c & 1, c >> 1 & 1, c >> 2 & 1);
    const glm::ivec3 q = i0 + o;
    const double w = (o.x ? f.x : 1 - f.x) * (o.y ? f.y : 1 - f.y) * (o.z ? f.z : 1 - f.z);
    sum[v[static_cast<size_t>((q.z * d.y + q.y) * d.x + q.x)]] += w;
  }
  int32_t best = -1;
  double best_w = -1;
  for (auto [label, w] : sum)
    if (w > best_w + 1e-6) best = label, best_w = w;  // ascending: ties keep the smaller
  return best;
}

TEST(LabelClassifier, WinnerIsTheLabelWithTheLargestInterpolatedIndicator) {
  const glm::ivec3 d(6, 5, 4);
  std::vector<uint16_t> v(static_cast<size_t>(d.x * d.y * d.z));
  std::mt19937 rng(7);
  for (uint16_t& x : v) x = static_cast<uint16_t>(rng() % 4);
  const VoxelGrid<uint16_t> g{v.data(), d};
  std::uniform_real_distribution<double> ux(0, d.x - 1), uy(0, d.y - 1), uz(0, d.z - 1);
  int checked = 0;
  for (int n = 0; n < 20000; ++n) {
    const glm::dvec3 p(ux(rng), uy(rng), uz(rng));
    const int32_t got = winning_label(g, glm::vec3(p), false);
    const int32_t want = expected_winner(v, d, p);
    // Near a tie float rounding may pick either; elsewhere the winner must match.
    if (got != want) {
      const float a = label_indicator(g, glm::vec3(p), got),
                  b = label_indicator(g, glm::vec3(p), want);
      EXPECT_NEAR(a, b, 1e-5f) << "at " << p.x << " " << p.y << " " << p.z;
    } else {
      ++checked;
    }
  }
  EXPECT_GT(checked, 19900);
}

// CSF (1) beside white matter (3): a trilinear value passes 2 (grey matter) between them; the
// classifier gives only 1 or 3, switching at the midpoint.
TEST(LabelClassifier, ABoundaryBetweenTwoLabelsNeverShowsAThird) {
  const glm::ivec3 d(4, 2, 2);
  std::vector<uint8_t> v(16);
  for (size_t i = 0; i < v.size(); ++i) v[i] = (i % 4) < 2 ? 1 : 3;  // x < 2: CSF, else WM
  const VoxelGrid<uint8_t> g{v.data(), d};
  for (int k = 0; k <= 300; ++k) {
    const float x = 3.0f * static_cast<float>(k) / 300.0f;
    const glm::vec3 p(x, 0.3f, 0.7f);
    const int32_t w = winning_label(g, p, false);
    EXPECT_TRUE(w == 1 || w == 3) << x;
    if (x < 1.49f) {
      EXPECT_EQ(w, 1) << x;
    }
    if (x > 1.51f) {
      EXPECT_EQ(w, 3) << x;
    }
    EXPECT_NEAR(g.sample(p), x < 1 ? 1.0f : x > 2 ? 3.0f : 1.0f + 2.0f * (x - 1.0f), 1e-5f);
  }
}

// A corner voxel of another label: the boundary is a smooth curve within the cell, not the
// cell's faces; nearest interpolation gives the voxel's cube (blocky).
TEST(LabelClassifier, SmoothBoundariesAreSubVoxelAndNearestIsBlocky) {
  const glm::ivec3 d(2, 2, 2);
  std::vector<uint8_t> v(8, 1);
  v[7] = 2;  // the corner (1, 1, 1)
  const VoxelGrid<uint8_t> g{v.data(), d};
  // Along the diagonal the indicator of 2 is t^3: it wins where t^3 > 1/2, t > 0.7937.
  for (float t : {0.70f, 0.78f, 0.80f, 0.9f}) {
    const int32_t want = t * t * t > 0.5f ? 2 : 1;
    EXPECT_EQ(winning_label(g, glm::vec3(t), false), want) << t;
  }
  // Nearest: the voxel whose centre is closest, a cube face at 0.5 on every axis.
  EXPECT_EQ(winning_label(g, glm::vec3(0.51f), true), 2);
  EXPECT_EQ(winning_label(g, glm::vec3(0.51f, 0.51f, 0.49f), true), 1);
  EXPECT_EQ(winning_label(g, glm::vec3(0.51f), false), 1);  // smooth: 0.51^3 < 1/2
  // The gradient of the winner's indicator points into it.
  const glm::vec3 n = label_gradient(g, glm::vec3(0.5f), 2);
  EXPECT_GT(n.x, 0.0f);
  EXPECT_FLOAT_EQ(n.x, n.y);
}

TEST(LabelLooks, TableLabelsPaletteAndHiddenOnes) {
  LabelMap m;
  m.entries = {{1, "csf", glm::vec3(0, 0, 1), 0.5f, true},
               {2, "gm", glm::vec3(0.5f), 1.0f, false},
               {300000, "far", glm::vec3(1, 0, 0), 1.0f, true}};
  m.palette_unlisted = false;
  const LabelLooks t(m);
  EXPECT_EQ(t.look(1), glm::vec4(0, 0, 1, 0.5f));
  EXPECT_EQ(t.look(2).a, 0.0f);       // hidden
  EXPECT_EQ(t.look(3).a, 0.0f);       // unlisted, with a table
  EXPECT_EQ(t.look(0).a, 0.0f);       // background
  EXPECT_EQ(t.look(300000).r, 1.0f);  // beyond the dense span: searched
  EXPECT_TRUE(t.any_shown_in(0.0f, 1.0f));
  EXPECT_FALSE(t.any_shown_in(1.5f, 299999.0f));
  EXPECT_FALSE(t.any_shown_in(2.0f, 2.0f));
  EXPECT_TRUE(t.any_shown_in(2.0f, 300000.0f));

  LabelMap p;  // no table: the default palette, background hidden
  const LabelLooks palette(p);
  EXPECT_EQ(palette.look(0).a, 0.0f);
  EXPECT_EQ(glm::vec3(palette.look(7)), default_label_color(7));
  EXPECT_EQ(glm::vec3(palette.look(70000)), default_label_color(70000));
  EXPECT_FALSE(palette.any_shown_in(0.0f, 0.0f));
  EXPECT_TRUE(palette.any_shown_in(0.0f, 1.0f));
  EXPECT_TRUE(palette.any_shown_in(-1.0f, 0.0f));

  LabelMap shown_zero;  // an inline table may show label 0
  shown_zero.entries = {{0, "outside", glm::vec3(1), 1.0f, true}};
  shown_zero.palette_unlisted = false;
  EXPECT_EQ(LabelLooks(shown_zero).look(0).a, 1.0f);
  EXPECT_TRUE(LabelLooks(shown_zero).any_shown_in(0.0f, 0.0f));
}

}  // namespace
}  // namespace imx
