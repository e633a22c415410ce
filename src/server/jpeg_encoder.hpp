// JPEG encoding of a rendered frame for the viewer while the user moves (small and fast to
// decode); still frames go out as PNG (imx::encode_png), lossless.
#pragma once
#include <string>

#include "intermix/image.hpp"

namespace imx::server {

// The image as written by write_png (sRGB, straight alpha) composited on black, as a baseline
// JPEG of `quality` 1..100. Throws imx::Error when libjpeg fails.
std::string encode_jpeg(const Image& image, int quality = 85);

}  // namespace imx::server
