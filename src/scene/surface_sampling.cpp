#include "scene/surface_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

#include <glm/glm.hpp>

#include "volume/voxel_grid.hpp"

namespace imx {
namespace {

constexpr int kMaxPointsPerVertex = 1024;

template <class T>
double sample_at(const VoxelGrid<T>& grid, const glm::dvec3& index) {
  const glm::dvec3 hi = glm::dvec3(grid.dims - 1);
  // Outside the box of voxel centres (with a little slack for rounding): no value.
  constexpr double kSlack = 1e-6;
  if (!(index.x >= -kSlack && index.y >= -kSlack && index.z >= -kSlack &&
        index.x <= hi.x + kSlack && index.y <= hi.y + kSlack && index.z <= hi.z + kSlack))
    return std::numeric_limits<double>::quiet_NaN();
  const float v = grid.sample(glm::vec3(glm::clamp(index, glm::dvec3(0.0), hi)));
  return no_data(v) ? std::numeric_limits<double>::quiet_NaN() : static_cast<double>(v);
}

}  // namespace

std::vector<double> sample_along_normals(const Mesh& mesh, const VolumeData& volume,
                                         const glm::dmat4& index_to_world,
                                         const SurfaceSampling& sampling) {
  const glm::dmat4 world_to_index = glm::inverse(index_to_world);
  const glm::dvec3 spacing(glm::length(glm::dvec3(index_to_world[0])),
                           glm::length(glm::dvec3(index_to_world[1])),
                           glm::length(glm::dvec3(index_to_world[2])));
  const double step = 0.5 * std::min({spacing.x, spacing.y, spacing.z});
  const double span = sampling.depth_to - sampling.depth_from;
  const int points =
      span > 0.0 ? std::clamp(static_cast<int>(std::ceil(span / step)) + 1, 2, kMaxPointsPerVertex)
                 : 1;
  std::vector<double> out(mesh.positions.size(), std::numeric_limits<double>::quiet_NaN());
  std::visit(
      [&](const auto& buffer) {
        using T = typename std::remove_cvref_t<decltype(buffer)>::value_type;
        const VoxelGrid<T> grid{buffer.data(), volume.dims};
        for (size_t v = 0; v < mesh.positions.size(); ++v) {
          const glm::dvec3 p(mesh.positions[v]);
          const glm::dvec3 n =
              v < mesh.normals.size() ? glm::dvec3(mesh.normals[v]) : glm::dvec3(0.0);
          const bool has_normal = glm::dot(n, n) > 0.0;
          double sum = 0.0, best = std::numeric_limits<double>::quiet_NaN();
          int count = 0;
          for (int k = 0; k < (has_normal ? points : 1); ++k) {
            const double d =
                points == 1 ? sampling.depth_from : sampling.depth_from + span * k / (points - 1);
            const glm::dvec3 q = has_normal ? p + d * glm::normalize(n) : p;
            const double s = sample_at(grid, glm::dvec3(world_to_index * glm::dvec4(q, 1.0)));
            if (std::isnan(s)) continue;
            ++count;
            sum += s;
            if (count == 1 || (sampling.reduce == SurfaceReduce::max ? s > best : s < best))
              best = s;
          }
          if (count > 0) out[v] = sampling.reduce == SurfaceReduce::mean ? sum / count : best;
        }
      },
      volume.voxels);
  return out;
}

}  // namespace imx
