// The dynamic fragment buffer methods (SPEC §6): dfb (exact) and dfb-sfm (SFM merging).
#pragma once
#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {

Image render_dfb(const Scene& scene, int spp, const RenderOptions& options);
Image render_dfb_sfm(const Scene& scene, int spp, const RenderOptions& options);

}  // namespace imx
