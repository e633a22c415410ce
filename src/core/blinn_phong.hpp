// Blinn-Phong shading of one point, shared by surfaces and volumes (pure, no allocation).
#pragma once
#include <cmath>
#include <span>

#include <glm/glm.hpp>

#include "intermix/scene.hpp"

namespace imx {

// A light resolved for one frame: headlights follow the viewer, directional ones are fixed.
struct ShadingLight {
  bool headlight = true;
  glm::vec3 to_light{0.0f};  // unit vector toward a directional light, world space
  glm::vec3 color{1.0f};     // colour times intensity
};

// x^n for x in [0, 1]: by repeated squaring when n is a whole number up to 1024 (the usual
// shininess; a few multiplies instead of std::pow's exp and log), else std::pow. Values below
// 1e-18 become 0 on the way: they cannot show, and denormal arithmetic is slow.
inline float specular_power(float x, float n) {
  if (!(n >= 0.0f && n <= 1024.0f && n == std::floor(n))) {
    float p = std::pow(x, n);
    return p < 1e-18f ? 0.0f : p;
  }
  float result = 1.0f;
  for (unsigned e = static_cast<unsigned>(n); e != 0; e >>= 1) {
    if (e & 1u) result *= x;
    if (result < 1e-18f) return 0.0f;
    x = x * x < 1e-18f ? 0.0f : x * x;
  }
  return result;
}

// Base colour lit by ambient + diffuse |N.L| + specular (N.H)^n, two-sided: the normal is
// flipped toward the viewer. `n` need not be normalized; a zero normal gives ambient +
// diffuse as if lit head-on (homogeneous regions of a volume have no gradient).
inline glm::vec3 blinn_phong(const Shading& s, const glm::vec3& base, glm::vec3 n,
                             const glm::vec3& to_eye, std::span<const ShadingLight> lights) {
  if (!s.enabled) return base;
  float len = glm::length(n);
  bool has_normal = len > 1e-12f;
  if (has_normal) {
    n /= len;
    if (glm::dot(n, to_eye) < 0.0f) n = -n;
  }
  glm::vec3 out = s.ambient * base;
  for (const ShadingLight& light : lights) {
    glm::vec3 l = light.headlight ? to_eye : light.to_light;
    if (!has_normal) {
      out += s.diffuse * base * light.color;
      continue;
    }
    float ndotl = glm::dot(n, l);
    if (ndotl <= 0.0f) continue;
    glm::vec3 h = glm::normalize(l + to_eye);
    float ndoth = std::max(0.0f, glm::dot(n, h));
    out += (s.diffuse * ndotl) * base * light.color +
           (s.specular * specular_power(ndoth, s.shininess)) * light.color;
  }
  return out;
}

// Resolves scene lights for a frame.
inline ShadingLight resolve_light(const Light& light) {
  ShadingLight out;
  out.headlight = light.type == LightType::headlight;
  if (!out.headlight) out.to_light = -glm::normalize(glm::vec3(light.direction));
  out.color = light.color * light.intensity;
  return out;
}

}  // namespace imx
