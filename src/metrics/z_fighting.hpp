// Z-fighting metric (SPEC §9): how uneven and how unstable a method's image is where coplanar
// surfaces coincide. A z-fighting-free method shows there a uniform blend that does not flicker.
#pragma once
#include <cstdint>
#include <span>

#include "intermix/image.hpp"

namespace imx {

struct ZFightingStats {
  long pixels = 0;                // pixels in the region
  double std_dev = 0.0;           // colour standard deviation over the region (RMS over RGB)
  double speckle = 0.0;           // the same of colour minus its 3x3 mean: noise, not gradients
  double jittered_std_dev = 0.0;  // std_dev of the jittered image
  double jitter_change = 0.0;     // RMS per-pixel colour change between the two images
};

// Display values (sRGB in [0, 1], as every metric) of `image` and of `jittered`, the same frame
// under a sub-pixel camera shift, over the pixels where `region` (width x height, row-major) is
// non-zero. Throws imx::Error when sizes differ.
ZFightingStats z_fighting(const Image& image, const Image& jittered,
                          std::span<const uint8_t> region);

}  // namespace imx
