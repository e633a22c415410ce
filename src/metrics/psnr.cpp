#include <cmath>
#include <limits>

#include "intermix/metrics.hpp"
#include "metrics/pixel_errors.hpp"

namespace imx {

double psnr_from(const PixelErrors& errors) {
  double mse = errors.sum_squared / (3.0 * errors.width * errors.height);
  if (mse == 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(1.0 / mse);
}

double psnr(const Image& a, const Image& b) {
  return psnr_from(measure_pixel_errors(a, b, false));
}

}  // namespace imx
