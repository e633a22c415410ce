// Post-classification of one volume sample: TF lookup, opacity for the step, Blinn-Phong.
#pragma once
#include <span>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

// Premultiplied contribution of volume `v` over a step of `len` mm sampled at depth `t`; none
// where the sample is no data.
inline glm::vec4 classify_sample(const PreparedVolume& v, const Ray& ray, double t, double len,
                                 std::span<const ShadingLight> lights) {
  glm::vec3 idx = v.to_index(ray.at(static_cast<float>(t)));
  const float s = v.grid.sample(idx);
  if (v.has_no_data && no_data(s)) return glm::vec4(0.0f);
  glm::vec4 tf = v.lut.lookup(s);
  if (tf.a <= 0.0f) return glm::vec4(0.0f);
  float a = correct_opacity(tf.a, static_cast<float>(len), v.lut.unit_distance());
  glm::vec3 rgb(tf);
  if (v.object->shading.enabled)
    rgb = blinn_phong(v.object->shading, rgb, v.world_gradient(idx), -ray.dir, lights);
  return glm::vec4(rgb * a, a);
}

}  // namespace imx
