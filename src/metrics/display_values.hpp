// Display values: what a person sees of a premultiplied linear pixel, the space every metric uses.
#pragma once
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/colour.hpp"
#include "intermix/image.hpp"

namespace imx {

// Over black a premultiplied colour keeps its RGB; srgb_encode also clamps to [0,1] (NaN -> 0).
inline glm::vec3 display_rgb(const glm::vec4& premultiplied) {
  return {srgb_encode(premultiplied.r), srgb_encode(premultiplied.g), srgb_encode(premultiplied.b)};
}

// Rec. 709 luminance of display values, the channel SSIM compares.
inline float display_luminance(const glm::vec3& display) {
  return 0.2126f * display.r + 0.7152f * display.g + 0.0722f * display.b;
}

// Throws imx::Error naming both sizes unless a and b are non-empty and equally sized.
void require_comparable(const Image& a, const Image& b);

}  // namespace imx
