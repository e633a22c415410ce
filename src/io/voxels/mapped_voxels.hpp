// Voxels read in place: an uncompressed file's voxels mapped read-only into memory instead of
// copied, so a volume costs file-backed pages the kernel may drop, not anonymous memory, and
// its first image does not wait for a copy. nibabel maps uncompressed images the same way.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>

#include "intermix/volume.hpp"
#include "io/voxels/raw_voxels.hpp"

namespace imx::detail {

// `count` voxels of `type` stored at byte `offset` of `path` in this machine's byte order, as a
// read-only view whose owner unmaps them; nullopt when they cannot be viewed as they lie (a
// type the renderer converts, an offset not aligned to the type, a file shorter than that, or
// a mapping the system refuses), and the caller reads them instead. A view of a file changed
// while it is rendered shows the change; one truncated under it ends the process (SIGBUS), as
// with any reader that maps files.
std::optional<VoxelStorage> map_voxels(const std::filesystem::path& path, uint64_t offset,
                                       RawType type, uint64_t count);

}  // namespace imx::detail
