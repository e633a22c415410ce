#include "frame/brick_coverage.hpp"

#include <algorithm>
#include <cmath>

namespace imx {

BrickCoverage::BrickCoverage(const PreparedVolume& v, const CameraModel& camera)
    : width_(camera.width()),
      height_(camera.height()),
      columns_((width_ + kBlockWidth - 1) / kBlockWidth),
      blocks_(static_cast<size_t>(columns_) * ((height_ + kBlockHeight - 1) / kBlockHeight), 0) {
  // Cells of `group`^3 bricks, at most kMaxCells a side, so that the per-frame work stays small
  // whatever the brick size: a cell is occupied when any of its bricks is. Without occupancy the
  // whole grid is one cell.
  constexpr int kMaxCells = 32;
  const glm::ivec3 voxels = v.grid.dims;
  const BrickOccupancy* occ = v.accel.occupancy.get();
  const glm::ivec3 bricks = occ ? occ->grid().dims : glm::ivec3(1);
  const int group = (std::max({bricks.x, bricks.y, bricks.z}) + kMaxCells - 1) / kMaxCells;
  const glm::ivec3 cells = (bricks + group - 1) / group;
  const glm::dvec3 cell_size = occ ? glm::dvec3(occ->grid().size * group)
                                   : glm::dvec3(glm::max(voxels - 1, glm::ivec3(1)));
  std::vector<uint8_t> occupied(static_cast<size_t>(cells.x) * cells.y * cells.z, occ ? 0 : 1);
  if (occ)
    for (int k = 0; k < bricks.z; ++k)
      for (int j = 0; j < bricks.y; ++j)
        for (int i = 0; i < bricks.x; ++i)
          if (occ->occupied({i, j, k}))
            occupied[(static_cast<size_t>(k / group) * cells.y + j / group) * cells.x + i / group] =
                1;

  // The image positions of the cells' corners: a lattice of (cells + 1)^3 points.
  const glm::ivec3 n = cells + 1;
  std::vector<glm::dvec2> at(static_cast<size_t>(n.x) * n.y * n.z);
  const glm::dmat4& to_world = v.object->index_to_world;
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) {
        const glm::dvec3 p = glm::min(glm::dvec3(i, j, k) * cell_size, glm::dvec3(voxels - 1));
        const glm::dvec3 c = camera.to_camera(glm::dvec3(to_world * glm::dvec4(p, 1.0)));
        const glm::dvec2 q = camera.project_camera(c);
        if ((camera.perspective() && !(c.z > camera.near_plane())) || !std::isfinite(q.x) ||
            !std::isfinite(q.y)) {
          std::fill(blocks_.begin(), blocks_.end(), 1);
          return;
        }
        at[(static_cast<size_t>(k) * n.y + j) * n.x + i] = q;
      }
  for (int k = 0; k < cells.z; ++k)
    for (int j = 0; j < cells.y; ++j)
      for (int i = 0; i < cells.x; ++i) {
        if (!occupied[(static_cast<size_t>(k) * cells.y + j) * cells.x + i]) continue;
        glm::dvec2 lo(INFINITY), hi(-INFINITY);
        for (int c = 0; c < 8; ++c) {
          const size_t m =
              (static_cast<size_t>(k + (c >> 2 & 1)) * n.y + j + (c >> 1 & 1)) * n.x + i + (c & 1);
          lo = glm::min(lo, at[m]), hi = glm::max(hi, at[m]);
        }
        mark(lo, hi);
      }
}

void BrickCoverage::mark(glm::dvec2 lo, glm::dvec2 hi) {
  // Pixel x has its centre at x + 0.5; one more pixel each side for rounding.
  const int x0 = static_cast<int>(std::clamp(std::floor(lo.x - 1.5), 0.0, double(width_)));
  const int x1 = static_cast<int>(std::clamp(std::ceil(hi.x + 0.5), 0.0, double(width_)));
  const int y0 = static_cast<int>(std::clamp(std::floor(lo.y - 1.5), 0.0, double(height_)));
  const int y1 = static_cast<int>(std::clamp(std::ceil(hi.y + 0.5), 0.0, double(height_)));
  if (x0 >= x1 || y0 >= y1) return;
  for (int r = y0 / kBlockHeight; r <= (y1 - 1) / kBlockHeight; ++r)
    std::fill_n(blocks_.begin() + static_cast<ptrdiff_t>(r) * columns_ + x0 / kBlockWidth,
                (x1 - 1) / kBlockWidth - x0 / kBlockWidth + 1, uint8_t{1});
}

}  // namespace imx
