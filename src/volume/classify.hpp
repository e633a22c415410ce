// Post-classification of one volume sample: TF lookup, opacity for the step, Blinn-Phong.
#pragma once
#include <span>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

// volume_look, but a label volume that is not shown still gives its table's colours: what MPR
// planes and slice views draw of it.
inline glm::vec4 table_look(const PreparedVolume& v, glm::vec3 idx) {
  if (v.labels.active())
    return v.grid.visit(
        [&](const auto& g) { return v.labels.look(winning_label(g, idx, v.labels.nearest())); });
  const float s = v.grid.sample(idx);
  if (v.has_no_data && no_data(s)) return glm::vec4(0.0f);
  if (v.colours.active()) return glm::vec4(v.colours.sample(idx), v.lut.lookup(s).a);
  return v.lut.lookup(s);
}

// The straight colour and opacity (of unit distance) a volume shows at index position `idx`:
// its TF at the trilinear value (a colour volume: its voxels' colour with the TF's opacity), or
// a label volume's winning label; none where no data.
inline glm::vec4 volume_look(const PreparedVolume& v, glm::vec3 idx) {
  if (v.labels.active() && !v.labels.shown()) return glm::vec4(0.0f);
  return table_look(v, idx);
}

// The winning label's contribution over a step of `len` mm, shaded with its indicator's gradient.
inline glm::vec4 classify_label_sample(const PreparedVolume& v, glm::vec3 idx, glm::vec3 to_eye,
                                       double len, std::span<const ShadingLight> lights) {
  return v.grid.visit([&](const auto& g) {
    const int32_t label = winning_label(g, idx, v.labels.nearest());
    const glm::vec4 look = v.labels.look(label);
    if (look.a <= 0.0f) return glm::vec4(0.0f);
    const float a = correct_opacity(look.a, static_cast<float>(len), v.labels.unit_distance());
    glm::vec3 rgb(look);
    if (v.object->shading.enabled)
      rgb = blinn_phong(v.object->shading, rgb, v.gradient_to_world * label_gradient(g, idx, label),
                        to_eye, lights);
    return glm::vec4(rgb * a, a);
  });
}

// Premultiplied contribution of volume `v` over a step of `len` mm sampled at depth `t`; none
// where the sample is no data.
inline glm::vec4 classify_sample(const PreparedVolume& v, const Ray& ray, double t, double len,
                                 std::span<const ShadingLight> lights) {
  glm::vec3 idx = v.to_index(ray.at(static_cast<float>(t)));
  if (v.labels.active()) return classify_label_sample(v, idx, -ray.dir, len, lights);
  const float s = v.grid.sample(idx);
  if (v.has_no_data && no_data(s)) return glm::vec4(0.0f);
  glm::vec4 tf = v.lut.lookup(s);
  if (tf.a <= 0.0f) return glm::vec4(0.0f);
  float a = correct_opacity(tf.a, static_cast<float>(len), v.lut.unit_distance());
  glm::vec3 rgb = v.colours.active() ? v.colours.sample(idx) : glm::vec3(tf);
  if (v.object->shading.enabled)
    rgb = blinn_phong(v.object->shading, rgb, v.world_gradient(idx), -ray.dir, lights);
  return glm::vec4(rgb * a, a);
}

}  // namespace imx
