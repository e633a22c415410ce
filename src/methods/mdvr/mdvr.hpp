// The mdvr method (SPEC §3): conventional multi-volume ray casting with binary surfaces.
#pragma once
#include "frame/frame_setup.hpp"
#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "methods/mdvr/mdvr_kernel.hpp"

namespace imx {

// mdvr's step (render.step_mm, else the smallest voxel pitch) and ERT, with the frame's volumes
// accelerated for that step; csg marches the same way.
MdvrParams prepare_mdvr(const Scene& scene, FrameSetup& frame);

Image render_mdvr(const Scene& scene, int spp, const RenderOptions& options);

}  // namespace imx
