#include "intermix/metrics.hpp"
#include "metrics/pixel_errors.hpp"

namespace imx {

ImageComparison compare_images(const Image& a, const Image& b) {
  PixelErrors errors = measure_pixel_errors(a, b, true);
  double pixels = double(errors.width) * errors.height;
  ImageComparison result;
  result.psnr_db = psnr_from(errors);
  result.ssim = ssim_from(errors);
  result.max_error = errors.max_error;
  result.frac_over_1 = errors.over_1 / pixels;
  result.frac_over_4 = errors.over_4 / pixels;
  result.frac_over_16 = errors.over_16 / pixels;
  return result;
}

}  // namespace imx
