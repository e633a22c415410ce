// PreparedVolume: a scene volume made ready for one frame (inverse transform, LUT, grid view).
#pragma once
#include <glm/glm.hpp>

#include "core/ray.hpp"
#include "core/specular_table.hpp"
#include "intermix/scene.hpp"
#include "volume/any_grid.hpp"
#include "volume/colour_grid.hpp"
#include "volume/label_classifier.hpp"
#include "volume/projection_tables.hpp"
#include "volume/tf_lut.hpp"
#include "volume/volume_acceleration.hpp"

namespace imx {

struct RayInterval {
  float t0 = 0.0f;
  float t1 = -1.0f;
  bool empty() const { return !(t1 > t0); }
};

struct PreparedVolume {
  const VolumeObject* object = nullptr;
  AnyGrid grid;
  glm::mat4 world_to_index{1.0f};
  glm::mat3 index_to_world_linear{1.0f};
  glm::mat3 gradient_to_world{1.0f};  // inverse-transpose: index-space gradient -> world space
  float min_pitch = 1.0f;             // smallest voxel spacing in mm
  TfLut lut;  // of a label volume: one entry, its most opaque label (max_opacity, unit_distance)
  LabelLooks labels;  // active for a label volume (VolumeObject::labels)
  // Active for a colour volume (VolumeData::colours): a sample's colour is its voxels' colour,
  // its opacity the TF's at the scalar (the luminance).
  ColourGrid colours;
  ProjectionLimits limits;       // the LUT's bounds for MIP and MinIP
  AttenuationTable attenuation;  // X-ray's line integral (empty for the other styles)
  SpecularTable specular;        // x^shininess of the volume's shading
  VolumeAcceleration accel;      // empty until a method that marches asks for it
  // Some voxels are NaN or infinite ("no data"): the kernels then test their samples with
  // no_data() and skip those, which volumes without such voxels never pay for.
  bool has_no_data = false;
  // The scalar marcher runs its x86-64-v3 copy (wide_scalar.hpp): the machine and the SIMD limit
  // allowed it when the volume was prepared.
  bool wide_scalar = false;

  explicit PreparedVolume(const VolumeObject& v);

  glm::vec3 to_index(glm::vec3 world) const {
    return glm::vec3(world_to_index * glm::vec4(world, 1.0f));
  }

  // The part of the ray inside the grid's hull [0, dims-1] and every clip plane, from t >= t_min.
  RayInterval intersect(const Ray& ray, float t_min = 0.0f) const;

  // Index-space gradient of the scalar field (central differences; one-sided beside no data).
  glm::vec3 index_gradient(glm::vec3 index_pos) const {
    return has_no_data ? grid.gradient_of_data(index_pos) : grid.gradient(index_pos);
  }

  // index_gradient() as the marchers take it: clamped_gradient where the grid allows it.
  glm::vec3 march_gradient(glm::vec3 index_pos) const {
    const glm::ivec3 d = grid.dims;
    if (has_no_data || d.x < 2 || d.y < 2 || d.z < 2) return index_gradient(index_pos);
    return grid.visit([&](const auto& g) { return g.clamped_gradient(index_pos); });
  }

  // World-space gradient of the scalar field at an index-space position.
  glm::vec3 world_gradient(glm::vec3 index_pos) const {
    return gradient_to_world * index_gradient(index_pos);
  }
};

}  // namespace imx
