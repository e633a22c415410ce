// Z-fighting of a method on a scene (SPEC §9): where coplanar surfaces coincide, and how the
// method's image behaves there, also under a sub-pixel camera shift.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "metrics/z_fighting.hpp"

namespace imx {

// Pixels whose centre ray meets surfaces of two different objects at depths within
// `relative_tolerance` * t of each other, and whose 8 neighbours do too (edges left out).
std::vector<uint8_t> coplanar_region(const Scene& scene, float relative_tolerance = 1e-5f);

// The camera moved sideways by `pixels` (x right, y down) at the target's distance: the image of
// the target plane shifts by that much.
Camera shifted_camera(const Scene& scene, glm::dvec2 pixels);

// Renders the scene with `options` at its camera and at the shifted one and measures the
// coplanar region of the unshifted camera. Throws imx::Error when the scene has no such region.
ZFightingStats measure_z_fighting(const Scene& scene, const RenderOptions& options,
                                  glm::dvec2 jitter_pixels = {0.37, 0.21});

}  // namespace imx
