// The reference method (SPEC §3): the ground truth every other method is measured against.
#pragma once
#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {

inline constexpr int kReferenceDefaultSpp = 16;

// Renders with a fine common step, exact surface splicing and `spp` stratified samples.
Image render_reference(const Scene& scene, int spp, const RenderOptions& options);

}  // namespace imx
