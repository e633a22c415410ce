// Shading of surface fragments: lit mesh surfaces and window/levelled planes (pure, premultiplied).
#pragma once
#include <algorithm>
#include <cmath>
#include <span>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "intermix/scene.hpp"
#include "volume/classify.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

// A mesh fragment: Blinn-Phong lit `base` colour (the material's, times the vertex colour where
// the mesh has them), premultiplied by the material's opacity. `normal` need not be unit
// length; `to_eye` is the unit vector back along the ray.
inline glm::vec4 shade_mesh_fragment(const Material& material, const glm::vec3& base,
                                     const glm::vec3& normal, const glm::vec3& to_eye,
                                     std::span<const ShadingLight> lights) {
  glm::vec3 rgb = blinn_phong(material.shading, base, normal, to_eye, lights);
  return {rgb * material.opacity, material.opacity};
}
// The same with the material's own colour.
inline glm::vec4 shade_mesh_fragment(const Material& material, const glm::vec3& normal,
                                     const glm::vec3& to_eye,
                                     std::span<const ShadingLight> lights) {
  return shade_mesh_fragment(material, material.color, normal, to_eye, lights);
}

// Grey level of `value` through a window of (centre, width): 0 below it, 1 above, linear inside.
inline float window_level(float value, float centre, float width) {
  return std::clamp((value - (centre - 0.5f * width)) / width, 0.0f, 1.0f);
}

// A plane fragment (unlit): `grey` times the plane colour, premultiplied by its opacity.
inline glm::vec4 shade_plane_fragment(const glm::vec3& color, float opacity, float grey) {
  return {grey * opacity * color, opacity};
}

// A plane fragment through a colour map (unlit): `rgb` times the plane colour, premultiplied.
inline glm::vec4 shade_plane_fragment(const glm::vec3& color, float opacity, const glm::vec3& rgb) {
  return {rgb * color * opacity, opacity};
}

// Whether a plane shows `value` at all: at or above its threshold (|value| when symmetric), so
// a thresholded overlay plane lets what lies behind it show elsewhere.
inline bool plane_value_shown(float value, float threshold, bool symmetric) {
  return (symmetric ? std::abs(value) : value) >= threshold;
}

// The value a plane shows at a world point of `volume`; false where the point lies outside the
// grid or the volume has no data there (NaN or inf voxels), where the plane has no fragment.
inline bool sample_plane_volume(const PreparedVolume& volume, const glm::vec3& world,
                                float& value) {
  glm::vec3 index = volume.to_index(world);
  if (!volume.grid.inside(index)) return false;
  value = volume.grid.sample(index);
  return !(volume.has_no_data && no_data(value));
}

// The colour a plane shows at a world point of a label volume: its winning label's (the
// classification volumes use, so a plane and a volume agree on every boundary); false outside the
// grid and where the label is hidden or background, where the plane is transparent.
inline bool sample_plane_labels(const PreparedVolume& volume, const glm::vec3& world,
                                glm::vec3& rgb) {
  glm::vec3 index = volume.to_index(world);
  if (!volume.grid.inside(index)) return false;
  const glm::vec4 look = table_look(volume, index);
  rgb = glm::vec3(look);
  return look.a > 0.0f;
}

// The colour a plane shows at a world point of a colour volume (VolumeData::colours): its
// voxels' colour, as the file stores it, in place of the windowed grey; false outside the grid.
inline bool sample_plane_colour(const PreparedVolume& volume, const glm::vec3& world,
                                glm::vec3& rgb) {
  glm::vec3 index = volume.to_index(world);
  if (!volume.grid.inside(index)) return false;
  rgb = volume.colours.sample(index);
  return true;
}

}  // namespace imx
