// ResolutionControl: moving frames fit the budget, the scale goes back up when frames are cheap,
// and a fixed per-frame cost does not pin the scale low.
#include "server/resolution_control.hpp"

#include <gtest/gtest.h>

namespace imx::server {
namespace {

constexpr double kFull = 512.0 * 512.0;

// A renderer whose frames cost `fixed` ms plus `per_pixel` ms a pixel; runs `frames` frames
// through the control and returns the scale it settles on.
double settle(ResolutionControl& control, double fixed, double per_pixel, int frames = 40) {
  double scale = 0.0;
  for (int i = 0; i < frames; ++i) {
    scale = control.pick(kFull, 512.0);
    control.record(scale, kFull, fixed + per_pixel * kFull * scale * scale);
  }
  return scale;
}

double cost(double fixed, double per_pixel, double scale) {
  return fixed + per_pixel * kFull * scale * scale;
}

TEST(ResolutionControl, StartsAtHalfSize) {
  ResolutionControl control(45.0);
  EXPECT_EQ(control.pick(kFull, 512.0), 0.5);
}

TEST(ResolutionControl, SettlesOnTheLargestScaleThatFits) {
  // 270 ms at full size (fusion with zslab on two cores): 0.375 takes 38 ms, 0.5 takes 67.
  ResolutionControl control(45.0);
  const double per_pixel = 270.0 / kFull;
  const double scale = settle(control, 0.0, per_pixel);
  EXPECT_EQ(scale, 0.375);
  EXPECT_LE(cost(0.0, per_pixel, scale), 45.0);
}

TEST(ResolutionControl, AFixedCostDoesNotPinTheScaleLow) {
  // 10 ms of every frame is fixed: the largest fitting scale is 0.5 (10 + 35 = 45 ms), which a
  // line through the origin, fitted at a small scale, would never predict to fit.
  ResolutionControl control(45.0);
  const double per_pixel = 140.0 / kFull;
  // A slow start (another program was busy) drives the scale down first.
  for (int i = 0; i < 3; ++i) control.record(control.pick(kFull, 512.0), kFull, 200.0);
  EXPECT_LT(control.pick(kFull, 512.0), 0.375);
  const double scale = settle(control, 10.0, per_pixel);
  EXPECT_GE(scale, 0.375);
  EXPECT_LE(cost(10.0, per_pixel, scale), 45.0);
}

TEST(ResolutionControl, GoesDownAtOnceWhenFramesGetSlow) {
  ResolutionControl control(45.0);
  EXPECT_EQ(settle(control, 0.0, 20.0 / kFull), 1.0);
  control.record(1.0, kFull, 400.0);
  EXPECT_LT(control.pick(kFull, 512.0), 1.0);
}

TEST(ResolutionControl, AnotherImageSizeForgetsTheMeasurements) {
  ResolutionControl control(45.0);
  settle(control, 0.0, 20.0 / kFull);
  EXPECT_EQ(control.pick(4 * kFull, 1024.0), 0.5);
}

TEST(ResolutionControl, KeepsTheShortSideAtTheFloorWhileItFits) {
  // One frame measured at 0.125 (64 px): 17 ms, half of it taken as fixed. 0.25 (128 px) is
  // predicted at 42.5 ms: within the budget, not within its 90% margin, which alone would pick
  // 0.1875 (96 px, 27.6 ms).
  ResolutionControl control(45.0);
  control.record(0.125, kFull, 17.0);
  EXPECT_NEAR(control.predicted(4), 42.5, 1e-9);
  EXPECT_EQ(control.pick(kFull, 512.0), 0.25);
}

TEST(ResolutionControl, GoesBelowTheFloorOnlyWhenTheFloorMissesTheBudget) {
  ResolutionControl control(45.0);
  const double scale = settle(control, 0.0, 1500.0 / kFull);  // 0.25 would take 94 ms
  EXPECT_LT(scale * 512.0, ResolutionControl::kMinShortSide);
  EXPECT_LE(cost(0.0, 1500.0 / kFull, scale), 45.0);
}

TEST(ResolutionControl, ASmallViewStartsAtTheFloor) {
  ResolutionControl control(45.0);
  EXPECT_EQ(control.pick(200.0 * 180.0, 180.0), 0.75);  // 135 px; half would be 90
}

}  // namespace
}  // namespace imx::server
