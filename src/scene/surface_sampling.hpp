// Volume-to-surface sampling: a volume's values at a mesh's vertices, along their normals.
#pragma once
#include <vector>

#include <glm/mat4x4.hpp>

#include "intermix/mesh.hpp"
#include "intermix/volume.hpp"

namespace imx {

enum class SurfaceReduce { mean, max, min };

struct SurfaceSampling {
  double depth_from = 0.0, depth_to = 0.0;  // mm along each vertex's unit normal (from <= to)
  SurfaceReduce reduce = SurfaceReduce::mean;
};

// For each vertex of `mesh` (world mm), the volume's trilinear value at the points
// p + d * normal, d from depth_from to depth_to in steps of at most half the volume's smallest
// voxel pitch (both ends included; one point when they are equal), reduced by mean, max or min
// over the points that have a value. A point has a value where it lies within the box of voxel
// centres (index 0 to dims - 1 on each axis, through the inverse of `index_to_world`) and the
// voxels around it are finite. NaN where no point has a value. A vertex with no normal (zero)
// is sampled at its position only. `index_to_world` places `volume`'s voxels (the object's).
std::vector<double> sample_along_normals(const Mesh& mesh, const VolumeData& volume,
                                         const glm::dmat4& index_to_world,
                                         const SurfaceSampling& sampling);

}  // namespace imx
