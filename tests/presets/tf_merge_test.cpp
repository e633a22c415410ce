#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "intermix/error.hpp"
#include "presets/tf_merge.hpp"
#include "volume/tf_lut.hpp"

namespace imx {
namespace {

TEST(TfMerge, PointsAtTheUnionCarryBothFunctionsExactly) {
  const std::vector<glm::dvec2> opacity = {{0, 0}, {10, 1}};
  const std::vector<glm::dvec4> color = {{5, 1, 0, 0}, {20, 0, 0, 1}};
  TransferFunction tf = merge_opacity_and_color(opacity, color);
  ASSERT_EQ(tf.points.size(), 4u);
  EXPECT_EQ(tf.points[0].value, 0.0);
  EXPECT_EQ(tf.points[0].rgba, glm::vec4(1, 0, 0, 0));  // colour below its first point: constant
  EXPECT_EQ(tf.points[1].value, 5.0);
  EXPECT_EQ(tf.points[1].rgba, glm::vec4(1, 0, 0, 0.5f));
  EXPECT_EQ(tf.points[2].value, 10.0);
  EXPECT_FLOAT_EQ(tf.points[2].rgba.r, 2.0f / 3.0f);
  EXPECT_FLOAT_EQ(tf.points[2].rgba.b, 1.0f / 3.0f);
  EXPECT_EQ(tf.points[2].rgba.a, 1.0f);
  EXPECT_EQ(tf.points[3].value, 20.0);
  EXPECT_EQ(tf.points[3].rgba, glm::vec4(0, 0, 1, 1));  // opacity beyond its last: constant
  // Anywhere between, the linear result equals both functions.
  for (double v = -5.0; v <= 25.0; v += 0.25) {
    glm::vec4 got = evaluate_transfer_function(tf, v);
    double a = std::clamp(v / 10.0, 0.0, 1.0);
    double red = v <= 5.0 ? 1.0 : v >= 20.0 ? 0.0 : 1.0 - (v - 5.0) / 15.0;
    EXPECT_NEAR(got.a, a, 1e-6) << v;
    EXPECT_NEAR(got.r, red, 1e-6) << v;
    EXPECT_NEAR(got.b, 1.0 - red, 1e-6) << v;
  }
}

TEST(TfMerge, EqualValuesMakeAStepWithBothSides) {
  const std::vector<glm::dvec2> opacity = {{0, 0}, {10, 0}, {10, 1}, {20, 1}};
  const std::vector<glm::dvec4> color = {{0, 1, 1, 1}, {20, 1, 1, 1}};
  TransferFunction tf = merge_opacity_and_color(opacity, color);
  ASSERT_EQ(tf.points.size(), 4u);
  EXPECT_EQ(tf.points[1].value, 10.0);
  EXPECT_EQ(tf.points[1].rgba.a, 0.0f);
  EXPECT_EQ(tf.points[2].value, 10.0);
  EXPECT_EQ(tf.points[2].rgba.a, 1.0f);
  EXPECT_FLOAT_EQ(evaluate_transfer_function(tf, 9.99).a, 0.0f);
  EXPECT_FLOAT_EQ(evaluate_transfer_function(tf, 10.01).a, 1.0f);
}

TEST(TfMerge, OnePointEachGivesOneConstantPoint) {
  TransferFunction tf = merge_opacity_and_color(std::vector<glm::dvec2>{{3, 0.25}},
                                                std::vector<glm::dvec4>{{3, 0.5, 0.5, 0.5}});
  ASSERT_EQ(tf.points.size(), 1u);
  EXPECT_EQ(tf.points[0].rgba, glm::vec4(0.5f, 0.5f, 0.5f, 0.25f));
  EXPECT_THROW(merge_opacity_and_color({}, std::vector<glm::dvec4>{{0, 1, 1, 1}}), Error);
}

}  // namespace
}  // namespace imx
