// Colour encodings: sRGB transfer curve and premultiplied/straight alpha conversions.
#pragma once
#include <cmath>

#include <glm/vec4.hpp>

namespace imx {

inline float srgb_encode(float linear) {
  if (!(linear > 0.0f)) return 0.0f;
  if (linear >= 1.0f) return 1.0f;
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

inline float srgb_decode(float encoded) {
  if (!(encoded > 0.0f)) return 0.0f;
  if (encoded >= 1.0f) return 1.0f;
  return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

// Premultiplied colour over an opaque or translucent straight background.
inline glm::vec4 over_background(const glm::vec4& premultiplied, const glm::vec4& background) {
  float t = 1.0f - premultiplied.a;
  return {premultiplied.r + t * background.a * background.r,
          premultiplied.g + t * background.a * background.g,
          premultiplied.b + t * background.a * background.b, premultiplied.a + t * background.a};
}

}  // namespace imx
