#include "movie/movie_frame.hpp"

#include <algorithm>
#include <cmath>

#include "core/colour.hpp"
#include "intermix/io.hpp"

namespace imx {

std::vector<uint8_t> movie_frame_rgb8(const Image& image) {
  const std::vector<uint8_t> rgba = display_rgba8(image);
  std::vector<uint8_t> rgb(image.size() * 3);
  for (size_t i = 0; i < image.size(); ++i) {
    if (rgba[i * 4 + 3] == 255) {
      std::copy_n(&rgba[i * 4], 3, &rgb[i * 3]);
      continue;
    }
    // Premultiplied linear colour is the colour over black; encoded as write_png encodes.
    const glm::vec4 p = image.data()[i];
    for (int c = 0; c < 3; ++c) {
      const float v = p[c] > 0.0f ? srgb_encode(std::min(p[c], 1.0f)) : 0.0f;  // NaN: black
      rgb[i * 3 + c] = static_cast<uint8_t>(std::lround(v * 255.0f));
    }
  }
  return rgb;
}

}  // namespace imx
