#include "volume/prepared_volume.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "core/math.hpp"
#include "intermix/error.hpp"
#include "volume/wide_scalar.hpp"

namespace imx {

namespace {

// What a label volume's LUT stands for: the opacity of its most opaque label, so that the
// questions every method asks of a LUT (is anything visible, how opaque can a step be) hold.
TransferFunction label_presence(const LabelLooks& looks) {
  TransferFunction tf;
  tf.points = {TfPoint{0.0, glm::vec4(1.0f, 1.0f, 1.0f, looks.max_opacity())}};
  tf.unit_distance = looks.unit_distance();
  return tf;
}

}  // namespace

PreparedVolume::PreparedVolume(const VolumeObject& v)
    : object(&v),
      grid(*v.data),
      labels(v.labels ? LabelLooks(*v.labels) : LabelLooks()),
      colours(v.labels ? ColourGrid() : ColourGrid(*v.data)),
      specular(v.shading.shininess) {
  lut = TfLut(v.labels ? label_presence(labels) : v.transfer_function);
  if (!all_finite(v.index_to_world))
    throw Error(fmt::format("volume '{}': transform has a non-finite entry", v.name));
  glm::dmat3 linear(v.index_to_world);
  if (std::abs(glm::determinant(linear)) < 1e-12)
    throw Error(fmt::format("volume '{}': transform is singular", v.name));
  world_to_index = glm::mat4(glm::inverse(v.index_to_world));
  index_to_world_linear = glm::mat3(linear);
  gradient_to_world = glm::mat3(glm::inverseTranspose(linear));
  min_pitch = static_cast<float>(
      std::min({glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2])}));
  limits = projection_limits(lut);
  has_no_data = has_non_finite_voxels(v.data);
  wide_scalar = wide_scalar_available();
  if (v.style == VolumeStyle::xray && v.xray_mode == XrayMode::integral)
    attenuation = AttenuationTable(lut);
}

RayInterval PreparedVolume::intersect(const Ray& ray, float t_min) const {
  // Slab test in index space: an affine map keeps the ray parameter t.
  glm::vec3 o = to_index(ray.origin);
  glm::vec3 d = glm::mat3(world_to_index) * ray.dir;
  glm::vec3 hi = glm::vec3(grid.dims - 1);
  RayInterval r{t_min, kInfinity};
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-12f) {
      if (o[a] < 0.0f || o[a] > hi[a]) return {};
      continue;
    }
    float inv = 1.0f / d[a];
    float ta = (0.0f - o[a]) * inv, tb = (hi[a] - o[a]) * inv;
    if (ta > tb) std::swap(ta, tb);
    r.t0 = std::max(r.t0, ta);
    r.t1 = std::min(r.t1, tb);
  }
  for (const ClipPlane& c : object->clip_planes) {
    glm::vec3 n(c.normal), p(c.point);
    float side = glm::dot(ray.origin - p, n);  // >= 0 is kept
    float rate = glm::dot(ray.dir, n);
    if (std::abs(rate) < 1e-12f) {
      if (side < 0.0f) return {};
      continue;
    }
    float t = -side / rate;
    if (rate > 0.0f)
      r.t0 = std::max(r.t0, t);
    else
      r.t1 = std::min(r.t1, t);
  }
  return r;
}

}  // namespace imx
