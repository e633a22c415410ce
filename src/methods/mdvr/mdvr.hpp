// The mdvr method (SPEC §3): conventional multi-volume ray casting with binary surfaces.
#pragma once
#include <span>

#include <glm/vec2.hpp>

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

// One volume and nothing else shown (nothing clipping it but its clip planes), with render.packets:
// every method's trace is then VolumeMarcher::composite (dvr) or the one projection or iso hit
// per ray, which the rays of a tile can share in vector lanes.
bool volume_packets_apply(const Scene& scene, const FrameSetup& frame);

// That case: per tile and sample position, the rays that meet the volume go through
// composite_packets() (dvr, its pieces shaded as `extent` says) or project_packets() together,
// each through its pixel at the position's `offsets` entry; a pixel is the mean of its samples,
// summed in order as render_per_sample sums them. `frame` accelerated for params.step.
Image render_volume_packets(const Scene& scene, const FrameSetup& frame, const MdvrParams& params,
                            SlabExtent extent, const RenderOptions& options,
                            std::span<const glm::vec2> offsets);

}  // namespace imx
