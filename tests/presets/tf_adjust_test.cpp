#include <gtest/gtest.h>

#include "presets/slicer_volume_property.hpp"
#include "presets/tf_adjust.hpp"
#include "presets/volume_presets.hpp"
#include "volume/tf_lut.hpp"

namespace imx {
namespace {

TEST(TfAdjust, ShiftMovesAndScaleStretchesAboutTheCentre) {
  TransferFunction tf;
  tf.points = {{100, glm::vec4(0)}, {200, glm::vec4(1)}, {400, glm::vec4(0.5f)}};
  shift_and_scale(tf, 200.0, 50.0, 2.0);  // v' = 200 + 2 (v - 200) + 50
  EXPECT_EQ(tf.points[0].value, 50.0);
  EXPECT_EQ(tf.points[1].value, 250.0);
  EXPECT_EQ(tf.points[2].value, 650.0);
  EXPECT_EQ(tf.points[1].rgba, glm::vec4(1));  // colours and opacities unchanged
}

// The documented invariant on a real preset: the result at v' is the original at
// (v' - shift - centre) / scale + centre.
TEST(TfAdjust, APresetMovedEvaluatesToTheOriginalAtTheMappedValue) {
  SlicerVolumeProperty p = *find_volume_preset("ct-muscle");
  const TransferFunction original = to_transfer_function(p);
  const double centre = adjust_centre(p), shift = -120.0, scale = 0.6;
  EXPECT_DOUBLE_EQ(centre, 0.5 * (-155.407 + 419.736));  // the middle of the effective range
  TransferFunction moved = original;
  shift_and_scale(moved, centre, shift, scale);
  for (double v = -3500.0; v <= 3500.0; v += 7.3) {
    glm::vec4 want = evaluate_transfer_function(original, (v - shift - centre) / scale + centre);
    glm::vec4 got = evaluate_transfer_function(moved, v);
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(got[c], want[c], 1e-5) << v;
  }
}

TEST(TfAdjust, CentreIsThePointsMiddleWithoutAnEffectiveRange) {
  SlicerVolumeProperty p = *find_volume_preset("ct-x-ray");  // its effectiveRange is malformed
  EXPECT_FALSE(p.effective_range);
  EXPECT_DOUBLE_EQ(adjust_centre(p), 0.5 * (-3024.0 + 3071.0));
  SlicerVolumeProperty u = *find_volume_preset("uct-skull");  // "0 -1": empty
  EXPECT_FALSE(u.effective_range);
}

}  // namespace
}  // namespace imx
