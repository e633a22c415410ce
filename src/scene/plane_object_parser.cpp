// Parser for a "plane" object: a rectangle in world space, optionally showing a volume.
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/glm.hpp>

#include "core/edit_distance.hpp"
#include "core/math.hpp"
#include "presets/colormap.hpp"
#include "presets/window_presets.hpp"
#include "scene/reading_planes.hpp"
#include "scene/scene_parsers.hpp"
#include "scene/world_space.hpp"

namespace imx::scene_json {
namespace {

// Corners of the volume's voxel extent (half a voxel beyond the centres), in world space.
void world_bounds(const VolumeObject& v, glm::dvec3& lo, glm::dvec3& hi) {
  lo = glm::dvec3(std::numeric_limits<double>::infinity());
  hi = -lo;
  const glm::dvec3 d = glm::dvec3(v.data->dims) - 0.5;
  for (int c = 0; c < 8; ++c) {
    glm::dvec3 index((c & 1) ? d.x : -0.5, (c & 2) ? d.y : -0.5, (c & 4) ? d.z : -0.5);
    glm::dvec3 p = transform_point(v.index_to_world, index);
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
}

// The world axis least aligned with the normal, made perpendicular to it: +y unless the
// plane faces along y.
glm::dvec3 default_up(const glm::dvec3& normal) {
  glm::dvec3 axis =
      std::abs(normal.y) < 0.9 ? glm::dvec3(0.0, 1.0, 0.0) : glm::dvec3(0.0, 0.0, 1.0);
  return glm::normalize(axis - glm::dot(axis, normal) * normal);
}

}  // namespace

glm::dvec2 parse_window(const JsonReader& v) {
  if (v.json().is_string()) {
    const std::string name = v.string();
    if (std::optional<glm::dvec2> w = find_window_preset(name)) return *w;
    const std::vector<std::string> names = window_preset_names();
    v.fail(fmt::format("{} is not a window preset{}; they are: {}", v.text(),
                       did_you_mean(name, names), fmt::join(names, ", ")));
  }
  if (!v.json().is_array())
    v.fail("expected [centre, width] or a window preset name, got " + v.describe());
  glm::dvec2 w = v.vec2();
  if (!(w.y > 0.0)) v.at(1).fail(fmt::format("window width {} must be > 0", w.y));
  return w;
}

PlaneObject parse_plane_object(const JsonReader& r, const Scene& scene,
                               const std::map<std::string, std::string>& object_types,
                               MeshSpace space) {
  r.check_keys({"name", "type", "center", "normal", "up", "size", "volume", "window", "colormap",
                "threshold", "symmetric", "color", "opacity", "thickness", "visible", "slab"});
  PlaneObject p;
  p.name = r.get("name").string();
  const VolumeObject* volume = nullptr;
  if (auto v = r.find("volume")) {
    p.volume = find_volume(*v, v->string(), scene, object_types);
    volume = &scene.volumes[static_cast<size_t>(p.volume)];
  }
  glm::dvec3 lo(0.0), hi(0.0);
  if (volume != nullptr) world_bounds(*volume, lo, hi);

  if (auto v = r.find("center"))
    p.center = to_lps(v->vec3(Range::coordinate()), space);
  else if (volume != nullptr)
    p.center = 0.5 * (lo + hi);
  else
    r.fail("missing required key 'center' (only a plane with a \"volume\" defaults to its centre)");
  p.normal = to_lps(r.get("normal").direction(), space);
  if (auto v = r.find("up")) {
    glm::dvec3 up = to_lps(v->direction(), space);
    glm::dvec3 in_plane = up - glm::dot(up, p.normal) * p.normal;
    if (glm::length(in_plane) < 1e-6) v->fail(v->text() + " is parallel to the normal");
    p.up = glm::normalize(in_plane);
  } else {
    p.up = default_up(p.normal);
  }
  if (auto v = r.find("size")) {
    if (v->json().is_number())
      p.size = glm::dvec2(v->number(Range::length()));
    else if (v->json().is_array())
      p.size = v->vec2(Range::length());
    else
      v->fail("expected a positive number or [width, height], got " + v->describe());
  } else if (volume != nullptr) {
    p.size = glm::dvec2(glm::length(hi - lo));  // the bounding box diagonal covers any cut
  } else {
    r.fail("missing required key 'size' (only a plane with a \"volume\" defaults to covering it)");
  }
  if (auto v = r.find("window"))
    p.window = parse_window(*v);
  else if (volume != nullptr && volume->data)
    p.window = reading_window(*volume);  // the source's own (DICOM), else its robust range
  if (auto v = r.find("colormap")) p.colormap = parse_colormap(*v);
  for (const char* key : {"threshold", "symmetric"})
    if (r.has(key) && volume == nullptr)
      r.get(key).fail("applies only to a plane showing a \"volume\"");
  if (auto v = r.find("symmetric")) p.symmetric = v->boolean();
  if (auto v = r.find("threshold"))
    p.threshold = v->number(p.symmetric ? Range::non_negative() : Range::any());
  if (auto v = r.find("color")) p.color = v->color();
  if (auto v = r.find("opacity"))
    p.opacity = static_cast<float>(v->number(Range::closed(0.0, 1.0)));
  if (!parse_visible(r)) p.opacity = 0.0f;  // hidden
  if (auto v = r.find("thickness")) p.thickness = parse_thickness(*v);
  if (auto v = r.find("slab")) {
    if (volume == nullptr) v->fail("applies only to a plane showing a \"volume\"");
    p.slab = parse_slab(*v);
  }
  return p;
}

}  // namespace imx::scene_json
