// A measurement kept with a scene (the top-level "annotations", docs/viewer.md, "Measurements"):
// its points in world space (LPS mm). What it measures is src/measure/'s; the document holds
// them beside its Scene (SceneDocument::annotations), so that rendering never sees them.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace imx {

enum class AnnotationKind { ruler, angle, ellipse, polygon };

inline constexpr size_t kMaxAnnotations = 1000;     // per scene
inline constexpr size_t kMaxPolygonPoints = 256;    // per polygon ROI
inline constexpr size_t kMaxAnnotationLabel = 200;  // bytes of a label

struct Annotation {
  AnnotationKind kind = AnnotationKind::ruler;
  // ruler: its two ends; angle: three, the vertex in the middle; ellipse: its centre and the ends
  // of its two semi-axes; polygon: 3..kMaxPolygonPoints corners in one plane.
  std::vector<glm::dvec3> points;
  std::string volume;  // ROIs: the volume whose voxels the statistics take; "": the first
  std::string label;   // the user's text, drawn beside the measurement
};

// "ruler", "angle", "ellipse" or "polygon": what scene files call the kind.
inline const char* annotation_kind_name(AnnotationKind kind) {
  switch (kind) {
    case AnnotationKind::ruler:
      return "ruler";
    case AnnotationKind::angle:
      return "angle";
    case AnnotationKind::ellipse:
      return "ellipse";
    case AnnotationKind::polygon:
      return "polygon";
  }
  return "annotation";
}

}  // namespace imx
