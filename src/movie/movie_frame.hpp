// A rendered image as the bytes a movie codes: 8-bit sRGB RGB rows, top first.
#pragma once
#include <cstdint>
#include <vector>

#include "intermix/image.hpp"

namespace imx {

// The colours write_png stores for `image` where it is opaque; where it is not, the image over
// black (a movie has no alpha).
std::vector<uint8_t> movie_frame_rgb8(const Image& image);

}  // namespace imx
