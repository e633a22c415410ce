// Rendering in bricks: a scene whose volumes one process cannot hold whole (past 2^31 voxels,
// or past half the memory budget) rendered by one process part by part. The parts are those
// of a distributed render (partition.hpp: volumes cut into bricks with aprons and shared cut
// planes), loaded one at a time by region, each rendered into slab arrays that are merged
// into the frame's by the intermix kernel and then let go: memory holds one brick, not the
// volume (docs/big_data.md, "Volumes larger than memory").
#pragma once
#include "dist/brick_levels.hpp"
#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "scene/scene_document.hpp"

namespace imx {

// How many bricks `outline`'s largest volume needs for each brick, apron included, to hold at
// most a quarter of kMaxVoxels and a quarter of the memory budget; at least 1.
int bricks_needed(const Scene& outline);

// The fewest bricks a render with levels of detail is cut into, so that levels vary over the
// volume: near bricks fine, far ones coarse.
inline constexpr int kLodBricks = 8;

// The frame of `outline` (a scene document read with one-voxel regions, its automatic choices
// written out: placements, source_dims and transfer functions, no voxels) rendered with zslab
// in `bricks` parts, each loaded from the sources by region, with options.spp (0: the scene's),
// options.threads and options.progress (over all parts); throws imx::Cancelled once
// options.cancel is set (checked between bricks and as each renders).
// With `levels`, each brick of a volume read from an OME-Zarr pyramid reads the level the rule
// picks from the one that fits its pixels (brick_levels.hpp); else level 0.
struct BrickedFrame {
  Image image;
  int coarsest_level = 0;  // the coarsest pyramid level any brick read, relative to the document's
};
BrickedFrame render_in_bricks(const SceneDocument& outline, int bricks,
                              const RenderOptions& options, const BrickLevelRule& levels = {});

}  // namespace imx
