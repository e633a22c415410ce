#include "io/overlay/volume_overlay.hpp"

#include <algorithm>
#include <variant>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx::detail {

bool is_vertex_volume_shape(glm::ivec3 dims, size_t vertices) {
  const auto voxels =
      static_cast<size_t>(dims.x) * static_cast<size_t>(dims.y) * static_cast<size_t>(dims.z);
  return std::min({dims.x, dims.y, dims.z}) == 1 && voxels == vertices;
}

VertexOverlay volume_as_overlay(const VolumeData& volume, size_t vertex_count,
                                const std::string& what) {
  const glm::ivec3 d = volume.dims;
  if (volume.voxel_count() != vertex_count)
    throw Error(
        fmt::format("{}: {}x{}x{} = {} voxels, but the surface has {} vertices: not a "
                    "per-vertex map of it",
                    what, d.x, d.y, d.z, volume.voxel_count(), vertex_count));
  VertexOverlay out;
  out.claimed_vertices = vertex_count;
  out.values.resize(vertex_count);
  // VolumeData keeps x fastest, the order FreeSurfer numbers the vertices in.
  std::visit(
      [&](const auto& buffer) {
        for (size_t i = 0; i < vertex_count; ++i) out.values[i] = static_cast<double>(buffer[i]);
      },
      volume.voxels);
  return out;
}

}  // namespace imx::detail
