// Parser for a scene's top-level "annotations": rulers, angles and ROIs kept with the scene
// (docs/viewer.md, "Measurements"). Every geometry is checked here, so that what measures and
// draws an annotation never meets a degenerate one.
#include <cmath>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "scene/scene_parsers.hpp"
#include "scene/world_space.hpp"

namespace imx::scene_json {
namespace {

// Below this (mm, mm²) a length or an area is taken for none: the geometry measures nothing.
constexpr double kTinyMm = 1e-9;
// How far (mm) a polygon's corner may lie from the corners' plane: JSON keeps doubles exactly,
// so a polygon drawn in a view lies in its plane to rounding.
constexpr double kPlanarMm = 1e-3;

// The number of points each kind takes: [lo, hi].
std::pair<size_t, size_t> point_count(AnnotationKind kind) {
  switch (kind) {
    case AnnotationKind::ruler:
      return {2, 2};
    case AnnotationKind::angle:
    case AnnotationKind::ellipse:
      return {3, 3};
    case AnnotationKind::polygon:
      return {3, kMaxPolygonPoints};
  }
  return {0, 0};
}

void check_geometry(const JsonReader& points, const Annotation& a) {
  const std::vector<glm::dvec3>& p = a.points;
  if (a.kind == AnnotationKind::angle &&
      (glm::length(p[0] - p[1]) < kTinyMm || glm::length(p[2] - p[1]) < kTinyMm))
    points.fail(
        "an angle's arms (points[0] and points[2] from the vertex points[1]) must have "
        "length > 0");
  if (a.kind == AnnotationKind::ellipse &&
      glm::length(glm::cross(p[1] - p[0], p[2] - p[0])) < kTinyMm)
    points.fail(
        "an ellipse's semi-axes (points[1] and points[2] from the centre points[0]) must "
        "have length > 0 and not be parallel");
  if (a.kind != AnnotationKind::polygon) return;
  // Newell's normal: twice the vector area, exact for a planar polygon.
  glm::dvec3 n(0.0), centroid(0.0);
  for (size_t i = 0; i < p.size(); ++i) {
    n += glm::cross(p[i], p[(i + 1) % p.size()]);
    centroid += p[i] / static_cast<double>(p.size());
  }
  if (glm::length(n) < 2 * kTinyMm) points.fail("the polygon encloses no area");
  n = glm::normalize(n);
  for (size_t i = 0; i < p.size(); ++i)
    if (double d = std::abs(glm::dot(p[i] - centroid, n)); d > kPlanarMm)
      points.at(i).fail(fmt::format(
          "lies {:.3g} mm from the plane of the polygon's corners; a polygon ROI is flat", d));
}

Annotation parse_annotation(const JsonReader& r, MeshSpace space) {
  r.expect_object();
  r.check_keys({"kind", "points", "volume", "label"});
  Annotation a;
  const std::string kind = r.get("kind").choice({"ruler", "angle", "ellipse", "polygon"});
  for (AnnotationKind k : {AnnotationKind::ruler, AnnotationKind::angle, AnnotationKind::ellipse,
                           AnnotationKind::polygon})
    if (kind == annotation_kind_name(k)) a.kind = k;
  const JsonReader points = r.get("points");
  points.expect_array();
  const auto [lo, hi] = point_count(a.kind);
  if (points.size() < lo || points.size() > hi)
    points.fail(lo == hi
                    ? fmt::format("a {} has {} points, not {}", kind, lo, points.size())
                    : fmt::format("a {} has {} to {} points, not {}", kind, lo, hi, points.size()));
  for (size_t i = 0; i < points.size(); ++i)
    a.points.push_back(to_lps(points.at(i).vec3(Range::coordinate()), space));
  check_geometry(points, a);
  if (auto v = r.find("volume")) {
    if (a.kind != AnnotationKind::ellipse && a.kind != AnnotationKind::polygon)
      v->fail(fmt::format("a {} takes no volume (only the ROIs, ellipse and polygon, do)", kind));
    a.volume = v->string();
  }
  if (auto v = r.find("label")) {
    a.label = v->string();
    if (a.label.size() > kMaxAnnotationLabel)
      v->fail(fmt::format("{} bytes, more than the {} a label may have", a.label.size(),
                          kMaxAnnotationLabel));
  }
  return a;
}

}  // namespace

std::vector<Annotation> parse_annotations(const JsonReader& r, const Scene& scene,
                                          const std::map<std::string, std::string>& object_types,
                                          MeshSpace space) {
  r.expect_array();
  if (r.size() > kMaxAnnotations)
    r.fail(fmt::format("{} annotations, more than the {} a scene may have", r.size(),
                       kMaxAnnotations));
  std::vector<Annotation> out;
  for (size_t i = 0; i < r.size(); ++i) {
    const JsonReader item = r.at(i);
    out.push_back(parse_annotation(item, space));
    if (auto v = item.find("volume")) find_volume(*v, out.back().volume, scene, object_types);
  }
  return out;
}

}  // namespace imx::scene_json
