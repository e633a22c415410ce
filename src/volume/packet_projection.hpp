// project_packets: the projection styles and iso-surfaces (project_volume, find_iso_crossing)
// for many rays through one volume, a packet at a time in SIMD lanes, skipping bricks by their
// value ranges. Pure: no allocation, no exceptions.
#pragma once
#include <span>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "volume/packet_marcher.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

// Whether project_packets() marches volume `v` (style mip, minip, xray or iso) in vector lanes:
// it needs a grid of at least 2 voxels a side whose gathers fit int32 offsets.
// Otherwise it walks each ray with project_volume / find_iso_crossing, with the same results.
bool packet_projection_supported(const PreparedVolume& v);

// out[i] = the premultiplied colour of what project_volume (or, for iso, find_iso_crossing with
// `bisections` and `lights`) finds on rays[i]'s [t0, t1] at `step`, zero when nothing shows, up
// to float rounding of the sample positions. Neighbouring rays should be consecutive.
void project_packets(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                     int bisections, std::span<const ShadingLight> lights,
                     std::span<glm::vec4> out);

}  // namespace imx
