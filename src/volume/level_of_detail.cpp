#include "volume/level_of_detail.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/parallel.hpp"
#include "intermix/error.hpp"

namespace imx {

double pixel_footprint(const Camera& camera, int image_height, const glm::dvec3& lo,
                       const glm::dvec3& hi) {
  const double rows = std::max(image_height, 1);
  if (camera.projection == Projection::orthographic) return camera.ortho_height / rows;
  // A box's nearest depth along the view direction is one of its corners'.
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  double nearest = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 corner((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    nearest = std::min(nearest, glm::dot(corner - camera.eye, forward));
  }
  const double spread = 2.0 * std::tan(glm::radians(camera.fov_deg) / 2.0) / rows;
  return std::max(nearest, 0.0) * spread;
}

double longest_voxel_edge(const glm::dmat4& m) {
  return std::max({glm::length(glm::dvec3(m[0])), glm::length(glm::dvec3(m[1])),
                   glm::length(glm::dvec3(m[2]))});
}

void world_box(const glm::dmat4& index_to_world, glm::ivec3 lo, glm::ivec3 hi, glm::dvec3& box_lo,
               glm::dvec3& box_hi) {
  box_lo = glm::dvec3(std::numeric_limits<double>::infinity());
  box_hi = -box_lo;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec4 index((c & 1) ? hi.x - 1 : lo.x, (c & 2) ? hi.y - 1 : lo.y,
                           (c & 4) ? hi.z - 1 : lo.z, 1.0);
    const glm::dvec3 w(index_to_world * index);
    box_lo = glm::min(box_lo, w);
    box_hi = glm::max(box_hi, w);
  }
}

VolumeData halved(const VolumeData& data) {
  if (data.colours) throw Error("a colour volume has no coarser level");
  const glm::ivec3 d = data.dims, h = (d + 1) / 2;
  VolumeData out;
  out.dims = h;
  // Voxel i covers voxels 2i and 2i + 1: its centre lies at index 2i + 0.5.
  out.index_to_world =
      glm::scale(glm::translate(data.index_to_world, glm::dvec3(0.5)), glm::dvec3(2.0));
  std::visit(
      [&](const auto& buffer) {
        using T = std::remove_cv_t<std::remove_reference_t<decltype(*buffer.data())>>;
        std::vector<T> voxels(static_cast<size_t>(h.x) * h.y * h.z);
        const T* in = buffer.data();
        const auto at = [&](int i, int j, int k) {
          return static_cast<double>(in[(static_cast<size_t>(k) * d.y + j) * d.x + i]);
        };
        parallel_for(h.z, 0, [&](long k0, long k1) {
          for (int k = static_cast<int>(k0); k < k1; ++k) {
            const int za = 2 * k, zb = std::min(2 * k + 1, d.z - 1);
            for (int j = 0; j < h.y; ++j) {
              const int ya = 2 * j, yb = std::min(2 * j + 1, d.y - 1);
              T* row = voxels.data() + (static_cast<size_t>(k) * h.y + j) * h.x;
              for (int i = 0; i < h.x; ++i) {
                const int xa = 2 * i, xb = std::min(2 * i + 1, d.x - 1);
                const double mean =
                    (at(xa, ya, za) + at(xb, ya, za) + at(xa, yb, za) + at(xb, yb, za) +
                     at(xa, ya, zb) + at(xb, ya, zb) + at(xa, yb, zb) + at(xb, yb, zb)) /
                    8.0;
                if constexpr (std::is_floating_point_v<T>)
                  row[i] = static_cast<T>(mean);
                else
                  row[i] = static_cast<T>(std::lround(mean));
              }
            }
          }
        });
        out.voxels = VoxelBuffer<T>(std::move(voxels));
      },
      data.voxels);
  return out;
}

}  // namespace imx
