// Writes a volume as an OME-Zarr image (NGFF 0.4, Zarr v2) with its pyramid: level 0 the grid
// itself, each next level half the last along every axis (means of 2x2x2 voxels), down to one
// chunk. The source is read box by box in slabs of one chunk's slices, so memory holds a slab
// per level, never the volume (intermix convert BIG -o big.zarr; docs/big_data.md).
#pragma once
#include <filesystem>
#include <functional>

#include "intermix/volume.hpp"

namespace imx::detail {

struct OmeZarrWriteOptions {
  int chunk = 64;                        // chunk edge in voxels, every level
  std::function<void(double)> progress;  // finished fraction of level 0's slabs
};

// The number of levels write_ome_zarr writes for a grid of `dims`: halving until the largest
// axis fits one chunk.
int ome_zarr_level_count(glm::ivec3 dims, int chunk);

// Writes the grid `header` describes, its boxes read by `read_box` (each a slab of whole
// slices), to the folder `dir`: written whole into a temporary folder beside it, then renamed,
// so a failure leaves nothing. Refuses (imx::Error naming it) a `dir` that exists. Chunks are
// blosc (lz4, byte shuffle) as zarr-python writes by default; the placement is NGFF's scale
// and translation per level, plus, for a grid whose axes are not x, y, z (LPS) as they are,
// its whole index-to-world matrix under "intermix" (NGFF has no orientation).
void write_ome_zarr(const VolumeHeader& header,
                    const std::function<VolumeData(const VoxelBox&)>& read_box,
                    const std::filesystem::path& dir, const OmeZarrWriteOptions& options = {});

}  // namespace imx::detail
