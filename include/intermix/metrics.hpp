// Image quality metrics (SPEC §9): PSNR, SSIM and error fractions between two images.
// All compare what a person sees: each premultiplied linear pixel is composited over black (its
// RGB as is, alpha ignored), clamped to [0,1] and sRGB-encoded into display values in [0,1].
#pragma once
#include "intermix/image.hpp"

namespace imx {

struct ImageComparison {
  double psnr_db = 0.0;       // over RGB in [0,1] after compositing over black; inf when equal
  double ssim = 0.0;          // mean SSIM of display luminance, 8x8 windows, stride 4
  double max_error = 0.0;     // largest per-channel absolute difference
  double frac_over_1 = 0.0;   // fraction of pixels whose largest channel error exceeds 1/255
  double frac_over_4 = 0.0;   // ... 4/255
  double frac_over_16 = 0.0;  // ... 16/255
};

// Compares images of equal size; throws imx::Error when the sizes differ or one is empty.
ImageComparison compare_images(const Image& a, const Image& b);

double psnr(const Image& a, const Image& b);
double ssim(const Image& a, const Image& b);

// A heat map of the per-pixel error (black = equal, red/yellow/white = growing error);
// `scale` maps an error of 1/scale to full heat.
Image error_heat_map(const Image& a, const Image& b, double scale = 16.0);

}  // namespace imx
