// The k+-buffer methods (SPEC §6): kbuffer (k = render.k) and kbuffer-ofm (OFM store pass).
#pragma once
#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {

Image render_kbuffer(const Scene& scene, int spp, const RenderOptions& options);
Image render_kbuffer_ofm(const Scene& scene, int spp, const RenderOptions& options);

}  // namespace imx
