// Per-vertex maps that FreeSurfer stores as volumes (mri_surf2surf, mris_preproc, mri_glmfit:
// lh.thickness.fsaverage.mgh, sig.nii.gz): one voxel per vertex, the grid reshaped where one
// axis cannot hold them all (163842 vertices as 27307x1x6 in NIfTI-1, whose dims are 16-bit).
// Vertex v is voxel v in the file's order, x fastest, as nibabel's get_fdata().ravel(order='F')
// gives it; each frame is a map.
#pragma once
#include <cstddef>
#include <string>

#include <glm/vec3.hpp>

#include "intermix/volume.hpp"
#include "io/overlay/vertex_overlay.hpp"

namespace imx::detail {

// Whether a volume of `dims` voxels is a per-vertex map of a surface of `vertices` vertices: as
// many voxels as vertices and an axis of 1. A brain image has no axis of 1, so it never passes;
// a single slice would need exactly the surface's vertex count of pixels.
bool is_vertex_volume_shape(glm::ivec3 dims, size_t vertices);

// The volume's voxels as values of `vertex_count` vertices, x fastest. Throws imx::Error naming
// `what` when the voxel count is not the vertex count.
VertexOverlay volume_as_overlay(const VolumeData& volume, size_t vertex_count,
                                const std::string& what);

}  // namespace imx::detail
