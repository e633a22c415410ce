#include "annotate/annotation_overlay.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera_model.hpp"
#include "measure/measurement.hpp"

namespace imx {
namespace {

// An ellipse's outline in segments: smooth at any size a view shows.
constexpr int kEllipseSegments = 96;
// Camera-space depth (mm) in front of which a perspective segment is cut: the eye's plane
// projects nowhere.
constexpr double kNearMm = 1e-3;
// How many label heights a label moves down at most to clear the labels drawn before it.
constexpr int kMaxLabelShifts = 16;

// The world polyline an annotation draws (closed for ROIs: the first point again at the end).
std::vector<glm::dvec3> outline(const Annotation& a) {
  const std::vector<glm::dvec3>& p = a.points;
  if (a.kind == AnnotationKind::ellipse) {
    std::vector<glm::dvec3> out;
    for (int i = 0; i <= kEllipseSegments; ++i) {
      const double t = 2.0 * std::numbers::pi * i / kEllipseSegments;
      out.push_back(p[0] + std::cos(t) * (p[1] - p[0]) + std::sin(t) * (p[2] - p[0]));
    }
    return out;
  }
  std::vector<glm::dvec3> out = p;
  if (a.kind == AnnotationKind::polygon) out.push_back(p.front());
  return out;
}

}  // namespace

void draw_segment(Image& image, glm::dvec2 a, glm::dvec2 b, double width, const glm::vec3& colour) {
  const double r = 0.5 * width + 0.5;  // coverage falls from 1 to 0 over the last pixel
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min(a.x, b.x) - r)));
  const int x1 = std::min(image.width() - 1, static_cast<int>(std::ceil(std::max(a.x, b.x) + r)));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min(a.y, b.y) - r)));
  const int y1 = std::min(image.height() - 1, static_cast<int>(std::ceil(std::max(a.y, b.y) + r)));
  const glm::dvec2 d = b - a;
  const double dd = glm::dot(d, d);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const glm::dvec2 c(x + 0.5, y + 0.5);
      const double t = dd > 0.0 ? std::clamp(glm::dot(c - a, d) / dd, 0.0, 1.0) : 0.0;
      const double dist = glm::length(c - (a + t * d));
      const float cover = static_cast<float>(std::clamp(r - dist, 0.0, 1.0));
      if (cover <= 0.0f) continue;
      glm::vec4& dst = image.at(x, y);
      dst = glm::vec4(colour * cover, cover) + (1.0f - cover) * dst;
    }
}

void draw_annotations(Image& image, const Scene& scene, const std::vector<Annotation>& annotations,
                      const TextRaster* text) {
  if (annotations.empty() || image.empty()) return;
  const CameraModel camera(scene.camera, image.width(), image.height());
  const glm::vec3 colour(kAnnotationColour[0], kAnnotationColour[1], kAnnotationColour[2]);
  // Lines and labels a little wider on large images, as a reader sees them at a fixed size.
  const double width = std::max(2.0, std::min(image.width(), image.height()) / 256.0);
  std::vector<glm::ivec4> placed;  // the labels drawn so far: x, y, width, height
  for (const Annotation& a : annotations) {
    const std::vector<glm::dvec3> line = outline(a);
    for (size_t i = 0; i + 1 < line.size(); ++i) {
      glm::dvec3 p = camera.to_camera(line[i]), q = camera.to_camera(line[i + 1]);
      if (camera.perspective()) {  // cut at the near depth: what lies behind the eye is not seen
        if (p.z < kNearMm && q.z < kNearMm) continue;
        if (p.z < kNearMm) p += (q - p) * ((kNearMm - p.z) / (q.z - p.z));
        if (q.z < kNearMm) q += (p - q) * ((kNearMm - q.z) / (p.z - q.z));
      }
      draw_segment(image, camera.project_camera(p), camera.project_camera(q), width, colour);
    }
    for (const glm::dvec3& corner : a.points) {  // the picked points as dots
      const glm::dvec3 c = camera.to_camera(corner);
      if (camera.perspective() && c.z < kNearMm) continue;
      const glm::dvec2 s = camera.project_camera(c);
      draw_segment(image, s, s, 2.5 * width, colour);
    }
    if (!text) continue;
    const glm::dvec3 anchor = camera.to_camera(a.points.back());
    if (camera.perspective() && anchor.z < kNearMm) continue;
    const glm::dvec2 at = camera.project_camera(anchor);
    const TextBitmap label = text->render(measurement_text(a, measure(a, scene)));
    const int x = static_cast<int>(std::lround(at.x + 2 * width));
    int y = static_cast<int>(std::lround(at.y + 2 * width));
    // Below the labels it would cover (annotations seen edge-on share a line), a few at most.
    const auto overlaps = [&](const glm::ivec4& b) {
      return x < b.x + b.z && b.x < x + label.width && y < b.y + b.w && b.y < y + label.height;
    };
    for (int tries = 0;
         tries < kMaxLabelShifts && std::any_of(placed.begin(), placed.end(), overlaps); ++tries)
      y += label.height;
    placed.push_back({x, y, label.width, label.height});
    draw_text(image, label, x + 1, y + 1, glm::vec3(0.0f));  // a shadow: legible on any colour
    draw_text(image, label, x, y, colour);
  }
}

}  // namespace imx
