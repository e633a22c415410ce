// Channels of one microscopy image blended into one colour volume: each voxel's colour is the sum
// or the maximum of its channels' colours, each scaled by where the voxel lies in the channel's
// window; its scalar (what the opacity follows) is that scale, summed or the largest.
#pragma once
#include <span>
#include <string>

#include "intermix/volume.hpp"
#include "io/zarr/ome_channels.hpp"

namespace imx {

enum class ChannelBlend : uint8_t { add, max };

// `volumes[c]` is channel `looks[c]`'s grid (all of one grid). A channel's scale is 0 at or
// below its window's start (it adds nothing there) and 1 at or above its end; its colour is the
// sRGB RRGGBB decoded to linear, the blend is taken in linear light, clamped to 1, and stored as
// sRGB bytes (VolumeData::colours); the scalar is 0 to 255. A channel with no window is scaled
// over channel_window's. Throws imx::Error naming `what` when the grids differ.
VolumeData blend_channels(std::span<const VolumeData> volumes,
                          std::span<const detail::OmeChannel> looks, ChannelBlend blend,
                          const std::string& what);

}  // namespace imx
