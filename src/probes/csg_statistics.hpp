// CsgRayStatistics: how the csg method's interval classification splits a scene's rays (the
// seed's PSI, accepted ranges, per-step tests, inconsistent rays), measured by a 1-spp pass.
#pragma once
#include <cstdint>
#include <vector>

#include "intermix/scene.hpp"

namespace imx {

// A pixel of the image, for examples.
struct CsgPixel {
  int x = 0, y = 0;
  friend bool operator==(const CsgPixel&, const CsgPixel&) = default;
};

// Integer sums over one ray per pixel (at the pixel centre), so the result does not depend on
// the thread count. "Meeting" rays have a fragment of a CSG mesh or cross a CSG volume's span;
// the per-ray figures are over those, since every other ray has no interval at all.
struct CsgRayStatistics {
  int width = 0, height = 0;
  int64_t rays = 0;
  int64_t meeting = 0;
  int64_t intervals = 0;  // summed over the rays (CsgIntervals::intervals)
  int max_intervals = 0;
  int64_t ranges = 0;  // accepted ranges, summed
  int max_ranges = 0;
  int64_t tested = 0;        // rays with a range whose steps need the per-step test
  int64_t inconsistent = 0;  // rays whose fragments did not pair up
  std::vector<CsgPixel> inconsistent_examples;  // the first few, in row-major order

  static constexpr int kMaxExamples = 5;

  double mean_intervals() const { return per_meeting(intervals); }
  double mean_ranges() const { return per_meeting(ranges); }
  double tested_fraction() const { return per_meeting(tested); }

  friend bool operator==(const CsgRayStatistics&, const CsgRayStatistics&) = default;

 private:
  double per_meeting(int64_t n) const {
    return meeting > 0 ? static_cast<double>(n) / static_cast<double>(meeting) : 0.0;
  }
};

// One ray per pixel of the scene's image, classified exactly as render_csg's (same frame set-up,
// step, acceleration, CsgFrame and fragments); `threads` 0 = all cores. Throws imx::Error as
// render_csg does (no csg block, too many states, an empty expression, too many volumes).
CsgRayStatistics csg_ray_statistics(const Scene& scene, int threads = 0);

}  // namespace imx
