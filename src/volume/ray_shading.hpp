// RayShading: Blinn-Phong for the samples of one volume ray, with everything that is constant
// along the ray (light and half vectors, coefficients) worked out once. Pure, fixed-size.
#pragma once
#include <algorithm>
#include <cmath>
#include <span>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "core/specular_table.hpp"
#include "intermix/scene.hpp"
#include "volume/sample_formulas.hpp"
#include "volume/sample_ops.hpp"

namespace imx {

class RayShading {
 public:
  static constexpr int kMaxLights = 4;

  RayShading() = default;
  // `to_eye`: unit vector from the samples toward the viewer (minus the ray direction);
  // `specular`: x^shininess for `s`, kept by the caller.
  RayShading(const Shading& s, const SpecularTable& specular, std::span<const ShadingLight> lights,
             const glm::vec3& to_eye)
      : shading_(s), specular_(&specular), lights_(lights), to_eye_(to_eye) {
    count_ =
        lights.size() <= static_cast<size_t>(kMaxLights) ? static_cast<int>(lights.size()) : -1;
    for (int i = 0; i < count_; ++i) {
      to_light_[i] = lights[i].headlight ? to_eye : lights[i].to_light;
      glm::vec3 h = to_light_[i] + to_eye;
      float len = glm::length(h);
      half_[i] = len > 1e-12f ? h / len : glm::vec3(0.0f);  // a light straight behind never lights
      colour_[i] = lights[i].color;
    }
  }

  // The premultiplied colour `c` lit with world-space normal direction `n` (any length):
  // blinn_phong(shading, C / A, n, ...) * A without the division, the specular power read from
  // the table (relative error ~3e-5).
  glm::vec4 apply(const glm::vec4& c, glm::vec3 n) const {
    if (count_ < 0) {
      if (c.a <= 0.0f) return c;
      return {blinn_phong(shading_, glm::vec3(c) / c.a, n, to_eye_, lights_) * c.a, c.a};
    }
    glm::vec3 rgb(c);
    sample_formulas::blinn_phong<ScalarOps>(shading_, n, to_eye_, *this, count_, true, rgb, c.a);
    return {rgb, c.a};
  }

  // The lights as sample_formulas::blinn_phong reads them.
  void light(int k, glm::vec3& to_light, glm::vec3& half) const {
    to_light = to_light_[k], half = half_[k];
  }
  const glm::vec3& colour(int k) const { return colour_[k]; }
  float specular(float ndoth) const { return (*specular_)(ndoth); }

 private:
  Shading shading_;
  const SpecularTable* specular_ = nullptr;
  std::span<const ShadingLight> lights_;  // for more than kMaxLights lights
  glm::vec3 to_eye_{0.0f};
  int count_ = 0;  // lights resolved below, or -1: use the general blinn_phong
  glm::vec3 to_light_[kMaxLights];
  glm::vec3 half_[kMaxLights];
  glm::vec3 colour_[kMaxLights];
};

}  // namespace imx
