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
// accelerated for that step (accelerate_for_packets); csg marches the same way, never in lanes.
MdvrParams prepare_mdvr(const Scene& scene, FrameSetup& frame, bool packets_possible);

Image render_mdvr(const Scene& scene, int spp, const RenderOptions& options);

// One volume and nothing else shown (nothing clipping it but its clip planes), with render.packets:
// every method's trace is then VolumeMarcher::composite (dvr) or the one projection or iso hit
// per ray, which the rays of a tile can share in vector lanes.
bool volume_packets_apply(const Scene& scene, const FrameSetup& frame);

// Accelerates the frame's volumes for `steps` as scene.render says, except that `automatic`
// gradients are taken on the fly where the method would march that case in lanes
// (`packets_possible`) and volume_packets_apply holds: every ray of the frame is then in lanes,
// where the clamped on-the-fly gradient beat the precomputed copy on most scans and spares its
// memory and build time (docs/performance.md).
void accelerate_for_packets(const Scene& scene, FrameSetup& frame, std::span<const float> steps,
                            bool packets_possible);

// That case: per tile and sample position, the rays that meet the volume go through
// composite_packets() (dvr, its pieces shaded as `extent` says) or project_packets() together,
// each through its pixel at the position's `offsets` entry; a pixel is the mean of its samples,
// summed in order as render_per_sample sums them. `frame` accelerated for params.step.
Image render_volume_packets(const Scene& scene, const FrameSetup& frame, const MdvrParams& params,
                            SlabExtent extent, const RenderOptions& options,
                            std::span<const glm::vec2> offsets);

}  // namespace imx
