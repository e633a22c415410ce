// RankScene: what one process of a distributed render loads and renders of the whole scene.
#pragma once
#include "dist/partition.hpp"
#include "intermix/scene.hpp"

namespace imx {

// Which voxels rank `rank` reads of each volume object: its brick's read box, every voxel of a
// volume it renders whole, and one voxel of any other (which its scene then leaves out).
VolumeRegionChooser rank_regions(const Partition& partition, int rank, const Scene& outline);

// The scene rank `rank` renders, from `loaded` (the scene loaded with rank_regions): only its
// objects and bricks (each brick cut at its bounds), the hidden clip meshes its volumes need,
// and the whole scene's smallest voxel pitch and surface thicknesses pinned, so that its steps
// and slabs are those of a single-process render.
Scene rank_scene(const Scene& loaded, const Partition& partition, int rank);

}  // namespace imx
