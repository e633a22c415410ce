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
           (s.specular * std::pow(ndoth, s.shininess)) * light.color;
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
