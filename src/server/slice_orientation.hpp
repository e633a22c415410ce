// An oblique reading view's orientation as a `slice` message gives it (docs/viewer.md, "Thick
// slabs and oblique views"): the crosshair's rotation of LPS, checked to be one.
#pragma once
#include <glm/mat3x3.hpp>

#include "scene/json_reader.hpp"

namespace imx::server {

// "rotation": [[r00, r01, r02], [r10, r11, r12], [r20, r21, r22]] (rows; its columns are where
// L, P and S turn to): each entry a number in [-1, 1], the rows orthonormal within 1e-3 and the
// determinant +1 (no mirror). Throws imx::Error naming the entry or saying how it is not a
// rotation; returns it made exactly orthonormal.
glm::dmat3 parse_rotation(const scene_json::JsonReader& r);

}  // namespace imx::server
