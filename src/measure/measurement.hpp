// What an annotation measures (docs/viewer.md, "Measurements"): a ruler's length, an angle's
// degrees, an ROI's area and the statistics of a volume's voxels inside it; and the scene's
// measurements as JSON or CSV (`intermix info SCENE --annotations`).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "intermix/scene.hpp"
#include "measure/roi_statistics.hpp"
#include "scene/annotation.hpp"

namespace imx {

struct Measurement {
  AnnotationKind kind = AnnotationKind::ruler;
  double length_mm = 0.0;                   // ruler: between its ends; ROIs: the outline's length
  double angle_deg = 0.0;                   // angle: between its arms, 0..180
  double area_mm2 = 0.0;                    // ROIs
  std::optional<RoiStatistics> statistics;  // ROIs over a volume (none: the scene has none)
  std::string volume, units;                // the statistics' volume and its values' units
};

// The distance between two points, mm.
double ruler_length(const glm::dvec3& a, const glm::dvec3& b);
// The angle at `vertex` between the arms to `a` and `b`, degrees in [0, 180]; NaN for an arm of
// length 0.
double angle_degrees(const glm::dvec3& a, const glm::dvec3& vertex, const glm::dvec3& b);

// What `a` measures in `scene`; an ROI's statistics are over its volume's voxels (the first
// volume when it names none). Throws imx::Error for a volume `scene` lacks or geometry the scene
// parser refuses.
Measurement measure(const Annotation& a, const Scene& scene);

// A short text for drawing: "12.3 mm", "45.0°", "mean 40.1 ± 3.2 HU, 78.5 mm²", after the
// annotation's label when it has one.
std::string measurement_text(const Annotation& a, const Measurement& m);

// {"kind", "label", "points", "length_mm" | "angle_deg" | "area_mm2", "volume", "units",
// "voxels", "non_finite", "mean", "sd", "min", "max"}: one annotation's measurement.
nlohmann::json measurement_json(const Annotation& a, const Measurement& m);
// One CSV row per annotation under a header row: index, kind, label, length_mm, angle_deg,
// area_mm2, volume, units, voxels, mean, sd, min, max, points (x y z; ...). Empty cells where a
// kind has no value.
std::string measurements_csv(const Scene& scene, const std::vector<Annotation>& annotations);

}  // namespace imx
