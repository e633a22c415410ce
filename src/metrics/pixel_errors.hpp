// Per-pixel display-value errors between two images, gathered in one parallel pass.
#pragma once
#include <vector>

#include "intermix/image.hpp"

namespace imx {

struct PixelErrors {
  int width = 0;
  int height = 0;
  double sum_squared = 0.0;                     // over the RGB channels of all pixels
  double max_error = 0.0;                       // largest per-channel absolute difference
  long over_1 = 0;                              // pixels whose largest channel error exceeds 1/255
  long over_4 = 0;                              // ... 4/255
  long over_16 = 0;                             // ... 16/255
  std::vector<float> luminance_a, luminance_b;  // row-major, filled only when asked (for SSIM)
};

// Throws imx::Error unless a and b are non-empty and equally sized.
PixelErrors measure_pixel_errors(const Image& a, const Image& b, bool with_luminance);

// Metrics of a measurement, shared by the public functions and compare_images.
double psnr_from(const PixelErrors& errors);  // psnr.cpp
double ssim_from(const PixelErrors& errors);  // ssim.cpp, needs the luminance planes

}  // namespace imx
