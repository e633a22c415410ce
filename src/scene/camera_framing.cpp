#include "scene/camera_framing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>

#include "volume/value_sample.hpp"

namespace imx {
namespace {

// The image holds the box with this much room to spare along its tighter side.
constexpr double kMargin = 1.15;

void include(WorldBox& box, const glm::dvec3& p) {
  box.lo = glm::min(box.lo, p);
  box.hi = glm::max(box.hi, p);
}

// Towards the eye from the target, and the image's up, in LPS world coordinates.
struct ViewAxes {
  glm::dvec3 to_eye, up;
};

ViewAxes axes_of(PatientView view) {
  switch (view) {
    case PatientView::anterior:
      return {{0, -1, 0}, {0, 0, 1}};
    case PatientView::posterior:
      return {{0, 1, 0}, {0, 0, 1}};
    case PatientView::left:
      return {{1, 0, 0}, {0, 0, 1}};
    case PatientView::right:
      return {{-1, 0, 0}, {0, 0, 1}};
    case PatientView::superior:
      return {{0, 0, 1}, {0, -1, 0}};
    case PatientView::inferior:
      return {{0, 0, -1}, {0, -1, 0}};
  }
  return {{0, -1, 0}, {0, 0, 1}};
}

// Whether the transfer function gives `value` any opacity (constant beyond its end points).
bool opaque_at(const TransferFunction& tf, double value) {
  const std::vector<TfPoint>& p = tf.points;
  if (p.empty()) return false;
  if (value <= p.front().value) return p.front().rgba.a > 0.0f;
  for (size_t i = 1; i < p.size(); ++i)
    if (value <= p[i].value) return p[i - 1].rgba.a > 0.0f || p[i].rgba.a > 0.0f;
  return p.back().rgba.a > 0.0f;
}

// The index box (first and last voxel centres) of the voxels the transfer function shows, from
// a subsample of about a million voxels, grown by the sampling stride so that none is missed;
// empty (lo > hi) when none shows.
std::pair<glm::dvec3, glm::dvec3> shown_voxels(const VolumeData& data, const TransferFunction& tf) {
  constexpr double kMaxSamples = 1024.0 * 1024.0;
  glm::ivec3 lo(std::numeric_limits<int>::max()), hi(std::numeric_limits<int>::min());
  for_each_sampled_voxel(data, kMaxSamples, [&](int i, int j, int k, double s) {
    if (!opaque_at(tf, s)) return;
    lo = glm::min(lo, glm::ivec3(i, j, k));
    hi = glm::max(hi, glm::ivec3(i, j, k));
  });
  if (lo.x > hi.x) return {glm::dvec3(1.0), glm::dvec3(0.0)};
  const int stride = sample_stride(data, kMaxSamples);
  return {glm::max(glm::dvec3(lo - stride), glm::dvec3(0.0)),
          glm::min(glm::dvec3(hi + stride), glm::dvec3(data.dims - 1))};
}

void include_volume(WorldBox& box, const VolumeObject& v, bool shown_only) {
  if (!v.data) return;
  glm::dvec3 lo(0.0), hi = glm::dvec3(v.data->dims) - 1.0, offset(0.0);
  if (v.source_dims.x > 0 && v.source_dims != v.data->dims) {
    // Read by region, the data is a box of the source: frame the whole source, as every
    // process rendering part of it must.
    hi = glm::dvec3(v.source_dims) - 1.0;
    offset = glm::dvec3(v.region.lo);
  } else if (shown_only && v.style != VolumeStyle::xray) {
    // What shows of it: a small mask in a large grid fills the frame, not its empty grid.
    std::tie(lo, hi) = shown_voxels(*v.data, v.transfer_function);
    if (lo.x > hi.x) return;
  }
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 index((corner & 1) ? hi.x + 0.5 : lo.x - 0.5,
                           (corner & 2) ? hi.y + 0.5 : lo.y - 0.5,
                           (corner & 4) ? hi.z + 0.5 : lo.z - 0.5);
    include(box, glm::dvec3(v.index_to_world * glm::dvec4(index - offset, 1.0)));
  }
}

void include_plane(WorldBox& box, const PlaneObject& p) {
  const glm::dvec3 n = glm::normalize(p.normal);
  const glm::dvec3 up = glm::normalize(p.up - glm::dot(p.up, n) * n);
  const glm::dvec3 right = glm::cross(up, n);
  for (double a : {-0.5, 0.5})
    for (double b : {-0.5, 0.5}) include(box, p.center + a * p.size.x * right + b * p.size.y * up);
}

bool volume_shows(const VolumeObject& v) {
  return std::any_of(v.transfer_function.points.begin(), v.transfer_function.points.end(),
                     [](const TfPoint& p) { return p.rgba.a > 0.0f; });
}

}  // namespace

const std::vector<std::string>& patient_view_names() {
  static const std::vector<std::string> names = {"anterior", "posterior", "left",
                                                 "right",    "superior",  "inferior"};
  return names;
}

std::optional<PatientView> find_patient_view(std::string_view name) {
  const std::vector<std::string>& names = patient_view_names();
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<PatientView>(i);
  return std::nullopt;
}

WorldBox visible_bounds(const Scene& scene, bool whole_grids) {
  WorldBox shown, all;
  for (const VolumeObject& v : scene.volumes) {
    include_volume(all, v, false);
    if (volume_shows(v)) include_volume(shown, v, !whole_grids);
  }
  for (const MeshObject& m : scene.meshes) {
    if (!m.mesh) continue;
    const bool visible = m.material.opacity > 0.0f;
    for (const glm::vec3& p : m.mesh->positions) {
      include(all, glm::dvec3(p));
      if (visible) include(shown, glm::dvec3(p));
    }
  }
  for (const StreamlineObject& o : scene.streamlines) {
    if (!o.streamlines) continue;
    const double r = o.radius;
    for (const glm::vec3& p : o.streamlines->points)
      for (WorldBox* box : {&all, o.opacity > 0.0f ? &shown : nullptr})
        if (box) include(*box, glm::dvec3(p) - r), include(*box, glm::dvec3(p) + r);
  }
  for (const PlaneObject& p : scene.planes) {
    include_plane(all, p);
    if (p.opacity > 0.0f) include_plane(shown, p);
  }
  return shown.empty() ? all : shown;
}

Camera framed_camera(const Camera& camera, const WorldBox& box, PatientView view, double aspect) {
  const ViewAxes axes = axes_of(view);
  Camera framed = camera;
  framed.up = axes.up;
  if (box.empty()) {
    framed.target = glm::dvec3(0.0);
    framed.eye = 600.0 * axes.to_eye;
    return framed;
  }
  const glm::dvec3 centre = 0.5 * (box.lo + box.hi);
  const glm::dvec3 right = glm::cross(-axes.to_eye, axes.up);
  // The box's half extents across the image and along the view, from its eight corners.
  double half_width = 0.0, half_height = 0.0, half_depth = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p((corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                       (corner & 4) ? box.hi.z : box.lo.z);
    const glm::dvec3 d = p - centre;
    half_width = std::max(half_width, std::abs(glm::dot(d, right)));
    half_height = std::max(half_height, std::abs(glm::dot(d, axes.up)));
    half_depth = std::max(half_depth, std::abs(glm::dot(d, axes.to_eye)));
  }
  const double needed_half_height =
      kMargin * std::max({half_height, half_width / std::max(aspect, 1e-6), 1e-3});
  const double tan_half_fov = std::tan(glm::radians(camera.fov_deg) / 2.0);
  // The nearest face of the box fits; deeper parts look smaller in perspective.
  const double distance = half_depth + needed_half_height / tan_half_fov;
  framed.target = centre;
  framed.eye = centre + distance * axes.to_eye;
  framed.ortho_height = 2.0 * needed_half_height;
  return framed;
}

}  // namespace imx
