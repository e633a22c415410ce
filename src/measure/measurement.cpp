#include "measure/measurement.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "measure/planar_region.hpp"

namespace imx {
namespace {

// Points as an ellipse's outline takes them: enough for its length to 1e-4 relative.
constexpr int kEllipseSegments = 256;

double outline_length(const Annotation& a) {
  const std::vector<glm::dvec3>& p = a.points;
  double sum = 0.0;
  if (a.kind == AnnotationKind::ellipse) {
    const glm::dvec3 u = p[1] - p[0], v = p[2] - p[0];
    glm::dvec3 last = p[0] + u;
    for (int i = 1; i <= kEllipseSegments; ++i) {
      const double t = 2.0 * std::numbers::pi * i / kEllipseSegments;
      const glm::dvec3 q = p[0] + std::cos(t) * u + std::sin(t) * v;
      sum += glm::length(q - last);
      last = q;
    }
    return sum;
  }
  for (size_t i = 0; i < p.size(); ++i) sum += glm::length(p[(i + 1) % p.size()] - p[i]);
  return sum;
}

// A CSV cell: quoted when it holds a comma, a quote or a line break.
std::string csv_cell(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string number(double v) {
  return std::isfinite(v) ? fmt::format("{:.10g}", v) : "";
}

}  // namespace

double ruler_length(const glm::dvec3& a, const glm::dvec3& b) {
  return glm::length(b - a);
}

double angle_degrees(const glm::dvec3& a, const glm::dvec3& vertex, const glm::dvec3& b) {
  const glm::dvec3 u = a - vertex, v = b - vertex;
  const double lu = glm::length(u), lv = glm::length(v);
  if (!(lu > 0.0) || !(lv > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  // atan2 of |u×v| and u·v: accurate near 0 and 180 degrees, where acos is not.
  return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v)) * 180.0 / std::numbers::pi;
}

Measurement measure(const Annotation& a, const Scene& scene) {
  Measurement m;
  m.kind = a.kind;
  if (a.kind == AnnotationKind::ruler) {
    if (a.points.size() != 2) throw Error("a ruler has 2 points");
    m.length_mm = ruler_length(a.points[0], a.points[1]);
    return m;
  }
  if (a.kind == AnnotationKind::angle) {
    if (a.points.size() != 3) throw Error("an angle has 3 points");
    m.angle_deg = angle_degrees(a.points[0], a.points[1], a.points[2]);
    return m;
  }
  const PlanarRegion region = PlanarRegion::of(a);
  m.area_mm2 = region.area_mm2();
  m.length_mm = outline_length(a);
  const VolumeObject* volume = scene.volumes.empty() ? nullptr : &scene.volumes.front();
  if (!a.volume.empty()) {
    volume = nullptr;
    for (const VolumeObject& v : scene.volumes)
      if (v.name == a.volume) volume = &v;
    if (!volume) throw Error(fmt::format("annotation: no volume named '{}'", a.volume));
  }
  if (volume && volume->data) {
    m.statistics = roi_statistics(*volume, region);
    m.volume = volume->name;
    m.units = volume->units;
  }
  return m;
}

std::string measurement_text(const Annotation& a, const Measurement& m) {
  std::string text;
  switch (a.kind) {
    case AnnotationKind::ruler:
      text = fmt::format("{:.1f} mm", m.length_mm);
      break;
    case AnnotationKind::angle:
      text = fmt::format("{:.1f}°", m.angle_deg);
      break;
    default:
      text = fmt::format("{:.1f} mm²", m.area_mm2);
      if (m.statistics && m.statistics->voxels > 0)
        text = fmt::format("mean {:.4g} ± {:.3g}{}{}, {}", m.statistics->mean, m.statistics->sd,
                           m.units.empty() ? "" : " ", m.units, text);
  }
  return a.label.empty() ? text : a.label + ": " + text;
}

nlohmann::json measurement_json(const Annotation& a, const Measurement& m) {
  nlohmann::json points = nlohmann::json::array();
  for (const glm::dvec3& p : a.points) points.push_back({p.x, p.y, p.z});
  nlohmann::json j = {{"kind", annotation_kind_name(a.kind)}, {"points", points}};
  if (!a.label.empty()) j["label"] = a.label;
  const auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; };
  if (a.kind == AnnotationKind::ruler) j["length_mm"] = m.length_mm;
  if (a.kind == AnnotationKind::angle) j["angle_deg"] = finite(m.angle_deg);
  if (a.kind == AnnotationKind::ellipse || a.kind == AnnotationKind::polygon) {
    j["area_mm2"] = m.area_mm2;
    j["perimeter_mm"] = m.length_mm;
  }
  if (m.statistics) {
    const RoiStatistics& s = *m.statistics;
    j["volume"] = m.volume;
    j["units"] = m.units;
    j["voxels"] = s.voxels;
    j["non_finite"] = s.non_finite;
    j["mean"] = finite(s.mean);
    j["sd"] = finite(s.sd);
    j["min"] = finite(s.min);
    j["max"] = finite(s.max);
  }
  return j;
}

std::string measurements_csv(const Scene& scene, const std::vector<Annotation>& annotations) {
  std::string out =
      "index,kind,label,length_mm,angle_deg,area_mm2,volume,units,voxels,mean,sd,min,max,points\n";
  for (size_t i = 0; i < annotations.size(); ++i) {
    const Annotation& a = annotations[i];
    const Measurement m = measure(a, scene);
    const bool roi = a.kind == AnnotationKind::ellipse || a.kind == AnnotationKind::polygon;
    std::string points;
    for (const glm::dvec3& p : a.points)
      points += fmt::format("{}{} {} {}", points.empty() ? "" : "; ", number(p.x), number(p.y),
                            number(p.z));
    const RoiStatistics s = m.statistics.value_or(RoiStatistics{});
    const bool stats = m.statistics.has_value();
    out += fmt::format(
        "{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", i, annotation_kind_name(a.kind),
        csv_cell(a.label), a.kind == AnnotationKind::angle ? "" : number(m.length_mm),
        a.kind == AnnotationKind::angle ? number(m.angle_deg) : "", roi ? number(m.area_mm2) : "",
        csv_cell(m.volume), csv_cell(m.units), stats ? std::to_string(s.voxels) : "",
        stats ? number(s.mean) : "", stats ? number(s.sd) : "", stats ? number(s.min) : "",
        stats ? number(s.max) : "", points);
  }
  return out;
}

}  // namespace imx
