// A volume property as 3D Slicer keeps it: separate scalar-opacity, gradient-opacity and colour
// functions with their own points, and shading coefficients.
#pragma once
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "intermix/scene.hpp"

namespace imx {

struct SlicerVolumeProperty {
  std::string name;
  std::vector<glm::dvec2> scalar_opacity;    // (value, opacity), sorted by value
  std::vector<glm::dvec2> gradient_opacity;  // (gradient magnitude, opacity); intermix ignores it
  std::vector<glm::dvec4> color;             // (value, r, g, b), sorted by value
  bool shade = false;
  double ambient = 0.1, diffuse = 0.9, specular = 0.2, specular_power = 10.0;
  // The values the preset is about (Slicer's "effectiveRange"); centre of shift and scale.
  std::optional<glm::dvec2> effective_range;
};

// Slicer's flat function numbers as points: "x y x y ..." and "x r g b ...". The numbers must
// be sorted by x; a point at the x of the one before replaces it, as VTK does when Slicer adds
// the points one by one.
std::vector<glm::dvec2> slicer_opacity_points(std::span<const double> flat);
std::vector<glm::dvec4> slicer_color_points(std::span<const double> flat);

// True when the gradient opacity is 1 for every gradient magnitude >= 0, i.e. ignoring it
// changes nothing.
bool gradient_opacity_is_trivial(const SlicerVolumeProperty& p);

// The scalar opacity and colour merged into intermix's RGBA points (tf_merge.hpp), alphas per
// 1 mm: VTK's scalar opacity unit distance is 1 world unit unless set, and Slicer's files do
// not set it. The gradient opacity is left out: intermix has no gradient-opacity term.
TransferFunction to_transfer_function(const SlicerVolumeProperty& p);

// Slicer's shading as intermix's Blinn-Phong: on when "shade" is, shininess = specular power.
Shading to_shading(const SlicerVolumeProperty& p);

// The value shift and scale move a property about: the middle of its effective range where it
// has one, else the middle of the span of its points.
double adjust_centre(const SlicerVolumeProperty& p);

}  // namespace imx
