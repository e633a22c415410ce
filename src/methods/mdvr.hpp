// The mdvr method (SPEC §3): conventional multi-volume ray casting with binary surfaces.
#pragma once
#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {

Image render_mdvr(const Scene& scene, int spp, const RenderOptions& options);

}  // namespace imx
