// The cameras of a turntable: a camera turned about its up axis through its target.
#pragma once
#include <vector>

#include "intermix/scene.hpp"

namespace imx {

// `frames` copies of `camera` turned about the axis through its target along its up vector,
// evenly over `degrees` (frame 0 is `camera`; the last stops one step short of a full turn, so a
// looping movie repeats no frame). The same cameras as Python's intermix.orbit_cameras.
std::vector<Camera> orbit_cameras(const Camera& camera, int frames, double degrees = 360.0);

}  // namespace imx
