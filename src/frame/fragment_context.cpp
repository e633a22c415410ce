#include "frame/fragment_context.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "raster/rasterizer.hpp"

namespace imx {

namespace {

// Depth bounds of the scene's points for the camera: perspective t is at least the view depth
// and at most the distance to the eye; orthographic t is the view depth. Cutters that do not
// show have no fragments to weigh, so they do not count.
DepthRange scene_depth_range(const Scene& scene, const CameraModel& camera) {
  double lo = INFINITY, hi = 0.0;
  auto add = [&](const glm::dvec3& world) {
    glm::dvec3 c = camera.to_camera(world);
    lo = std::min(lo, c.z);
    hi = std::max(hi, camera.perspective() ? glm::length(c) : c.z);
  };
  const std::vector<bool> shown = shown_meshes(scene);
  for (size_t k = 0; k < scene.meshes.size(); ++k)
    if (scene.meshes[k].mesh && shown[k])
      for (const glm::vec3& p : scene.meshes[k].mesh->positions) add(glm::dvec3(p));
  for (const StreamlineObject& o : scene.streamlines) {
    if (!o.streamlines || o.streamlines->points.empty() || !(o.opacity > 0.0f)) continue;
    glm::vec3 box_lo(INFINITY), box_hi(-INFINITY);  // the tubes' box: 8 corners, not every point
    for (const glm::vec3& p : o.streamlines->points)
      box_lo = glm::min(box_lo, p), box_hi = glm::max(box_hi, p);
    const glm::dvec3 r(o.radius);
    for (int i = 0; i < 8; ++i)
      add(glm::dvec3(i & 1 ? box_hi.x : box_lo.x, i & 2 ? box_hi.y : box_lo.y,
                     i & 4 ? box_hi.z : box_lo.z) +
          (glm::dvec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1) * r));
  }
  for (const PlaneObject& p : scene.planes) {
    if (!shown_plane(p)) continue;
    glm::dvec3 n = glm::normalize(p.normal);
    glm::dvec3 v = glm::normalize(p.up - glm::dot(p.up, n) * n);
    glm::dvec3 u = glm::cross(v, n);
    for (int i = 0; i < 4; ++i)
      add(p.center + (i & 1 ? 0.5 : -0.5) * p.size.x * u + (i & 2 ? 0.5 : -0.5) * p.size.y * v);
  }
  for (const VolumeObject& v : scene.volumes) {
    if (!v.data) continue;
    glm::dvec3 d = glm::dvec3(v.data->dims) - 1.0;
    for (int i = 0; i < 8; ++i) {
      glm::dvec4 idx(i & 1 ? d.x : 0.0, i & 2 ? d.y : 0.0, i & 4 ? d.z : 0.0, 1.0);
      add(glm::dvec3(v.index_to_world * idx));
    }
  }
  DepthRange r;
  if (!(hi > 0.0)) return r;
  r.far = static_cast<float>(hi);
  r.near = static_cast<float>(std::max(lo, 1e-3 * hi));
  if (!(r.far > r.near)) r.far = r.near * 2.0f;
  return r;
}

}  // namespace

InSlabInterpolation interpolation_of(const RenderSettings& render) {
  InSlabInterpolation m;
  m.mode = render.interpolation == "hvi"     ? Interpolation::hvi
           : render.interpolation == "blend" ? Interpolation::blend
                                             : Interpolation::ovi;
  m.beta = static_cast<float>(render.beta);
  return m;
}

FragmentContext::FragmentContext(const Scene& scene, const char* method, bool zero_thickness)
    : frame(scene) {
  frame.require_per_sample_support(method);
  hybrid.step = static_cast<float>(frame.ray_step(scene.render));
  hybrid.ert = static_cast<float>(scene.render.ert_threshold);
  hybrid.interpolation = interpolation_of(scene.render);
  frame.accelerate(hybrid.step, MarchSettings::from(scene.render));
  thickness = SurfaceThickness(scene, frame.camera, zero_thickness);
  depth_range = scene_depth_range(scene, frame.camera);
}

}  // namespace imx
