// Depth peeling with ray casting between layers (SPEC §7), L = render.peel_layers: opaque
// geometry is a depth buffer that ends each ray, only transparent fragments are peeled.
#pragma once
#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {

Image render_peel(const Scene& scene, int spp, const RenderOptions& options);

}  // namespace imx
