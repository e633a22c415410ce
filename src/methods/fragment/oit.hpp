// Order-independent transparency baselines (SPEC §6): wboit (weighted blended) and mboit
// (moment-based, 4 power moments).
#pragma once
#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {

Image render_wboit(const Scene& scene, int spp, const RenderOptions& options);
Image render_mboit(const Scene& scene, int spp, const RenderOptions& options);

}  // namespace imx
