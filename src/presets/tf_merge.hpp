// Separate opacity and colour functions, each with its own points, as one RGBA transfer function.
#pragma once
#include <span>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "intermix/scene.hpp"

namespace imx {

// `opacity` (value, alpha) and `color` (value, r, g, b), both sorted by value and non-empty,
// merged at the union of their values. Between two neighbours of the union both functions are
// linear, and beyond the ends both are constant, so the linear RGBA result equals them exactly.
// Equal values in one function make a step: the first point is the value from the left, the
// last the value from the right; the result then has two points at that value.
// unit_distance is left at its default (1 mm).
TransferFunction merge_opacity_and_color(std::span<const glm::dvec2> opacity,
                                         std::span<const glm::dvec4> color);

}  // namespace imx
