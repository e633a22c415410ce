// Colour encodings: sRGB transfer curve and premultiplied/straight alpha conversions. The one
// owner of the colour rule (docs/colour.md): every colour a user gives (scene files, presets,
// colour tables, colour maps, mesh and overlay files) is a display (sRGB) colour, decoded once
// where it enters by display_to_linear; the renderer works in linear light and encodes on output.
#pragma once
#include <cmath>

#include <glm/vec3.hpp>
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

// A display (sRGB) colour as linear RGB: how a colour a user gives enters the renderer.
inline glm::vec3 display_to_linear(const glm::vec3& display) {
  return {srgb_decode(display.r), srgb_decode(display.g), srgb_decode(display.b)};
}

// The same with an opacity, which stays as given.
inline glm::vec4 display_to_linear(const glm::vec4& display) {
  return {display_to_linear(glm::vec3(display)), display.a};
}

// The display value srgb_decode takes back to `linear` exactly, where one exists (as for every
// value decoded from one): a colour handed back to a user and given again decodes to the same
// float. Searches a few floats about srgb_encode's answer; else that answer.
inline float srgb_encode_exact(float linear) {
  const float e = srgb_encode(linear);
  float below = e, above = e;
  for (int i = 0; i < 8 && srgb_decode(e) != linear; ++i) {
    below = std::nextafter(below, 0.0f);
    above = std::nextafter(above, 1.0f);
    if (srgb_decode(below) == linear) return below;
    if (srgb_decode(above) == linear) return above;
  }
  return e;
}

// A linear colour as the display colour that shows it: how a colour goes back to a user (the
// viewer's lists and edits, Python's Mesh.colors), so that what was given is what comes back.
inline glm::vec3 linear_to_display(const glm::vec3& linear) {
  return {srgb_encode_exact(linear.r), srgb_encode_exact(linear.g), srgb_encode_exact(linear.b)};
}

// Premultiplied colour over an opaque or translucent straight background.
inline glm::vec4 over_background(const glm::vec4& premultiplied, const glm::vec4& background) {
  float t = 1.0f - premultiplied.a;
  return {premultiplied.r + t * background.a * background.r,
          premultiplied.g + t * background.a * background.g,
          premultiplied.b + t * background.a * background.b, premultiplied.a + t * background.a};
}

}  // namespace imx
