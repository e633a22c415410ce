// The look of one channel of a multi-channel microscopy image (OME "omero" metadata): a ramp in
// the channel's colour over its display window, transparent at the window's start, so a voxel
// below it adds nothing and channels of one grid add up as fluorescence does.
#pragma once
#include "intermix/volume.hpp"
#include "io/zarr/ome_channels.hpp"
#include "scene/automatic_look.hpp"

namespace imx {

// The colour is OME's sRGB-encoded RRGGBB, decoded to linear RGB (as mesh-file colours are):
// transfer function colours are linear. No window: the range omero gives, else the voxels'.
AutomaticLook channel_look(const detail::OmeChannel& channel, const VolumeData& data);

// The value range a channel is shown over: its window, else its range, else the voxels'. `from`
// gets which, for a note.
glm::dvec2 channel_window(const detail::OmeChannel& channel, const VolumeData& data,
                          const char** from = nullptr);

}  // namespace imx
