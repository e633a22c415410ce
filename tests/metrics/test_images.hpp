// Test images built in display space, so expected metrics need no sRGB arithmetic.
#pragma once
#include <random>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/colour.hpp"
#include "intermix/image.hpp"

namespace imx::test {

inline glm::vec4 from_display(const glm::vec3& d) {
  return {srgb_decode(d.r), srgb_decode(d.g), srgb_decode(d.b), 1.0f};
}

template <class Fn>
Image display_image(int width, int height, Fn display_at) {
  Image image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) image.at(x, y) = from_display(display_at(x, y));
  return image;
}

// Smooth gradients plus a checker, so windows have structure for SSIM to lose.
inline Image structured_image(int width, int height) {
  return display_image(width, height, [&](int x, int y) {
    float checker = ((x / 4 + y / 4) % 2) ? 0.15f : 0.0f;
    return glm::vec3(0.2f + 0.5f * x / width + checker, 0.3f + 0.4f * y / height, 0.6f - checker);
  });
}

// A copy with uniform display-space noise of the given amplitude, from a fixed seed.
inline Image noisy_copy(const Image& image, float amplitude, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> noise(-amplitude, amplitude);
  Image out(image.width(), image.height());
  for (size_t i = 0; i < image.size(); ++i) {
    glm::vec4 p = image.data()[i];
    glm::vec3 d(srgb_encode(p.r) + noise(rng), srgb_encode(p.g) + noise(rng),
                srgb_encode(p.b) + noise(rng));
    out.data()[i] = from_display(d);
  }
  return out;
}

}  // namespace imx::test
