#include "volume/octant_distance.hpp"

#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/parallel.hpp"

namespace imx {

void octant_distance(std::span<const uint8_t> occupied, glm::ivec3 dims, std::span<uint8_t> out) {
  // One plane per octant with a one-cell border of 255 (empty past the grid), which removes
  // every bounds test from the sweeps.
  const ptrdiff_t px = dims.x + 2, py = dims.y + 2, pz = dims.z + 2;
  const ptrdiff_t sy = px, sz = px * py, plane = px * py * pz;
  std::vector<uint8_t> d(static_cast<size_t>(kOctants * plane), 255);
  parallel_for(kOctants, 0, [&](long first, long last) {
    std::vector<uint8_t> rows(static_cast<size_t>(dims.x));
    for (long o = first; o < last; ++o) {
      uint8_t* const p = d.data() + o * plane;
      const int sx = (o & 1) ? -1 : 1;
      const ptrdiff_t ay = (o & 2) ? -sy : sy, az = (o & 4) ? -sz : sz;
      // Rows ahead first (toward the octant in y and z), so that each cell's six neighbours ahead
      // in other rows are final; the seventh, ahead in x, comes from the sweep along the row.
      for (int kk = 0; kk < dims.z; ++kk) {
        const int k = az > 0 ? dims.z - 1 - kk : kk;
        for (int jj = 0; jj < dims.y; ++jj) {
          const int j = ay > 0 ? dims.y - 1 - jj : jj;
          uint8_t* const row = p + (k + 1) * sz + (j + 1) * sy + 1;
          for (int i = 0; i < dims.x; ++i) {
            const uint8_t* c = row + i;
            rows[i] = std::min({c[ay], c[az], c[ay + az], c[sx + ay], c[sx + az], c[sx + ay + az]});
          }
          const uint8_t* occ = occupied.data() + (static_cast<size_t>(k) * dims.y + j) * dims.x;
          for (int ii = 0; ii < dims.x; ++ii) {
            const int i = sx > 0 ? dims.x - 1 - ii : ii;
            const int next = std::min(rows[i], row[i + sx]);
            row[i] = occ[i] ? 0 : static_cast<uint8_t>(std::min(next + 1, 255));
          }
        }
      }
    }
  });
  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i) {
        const size_t n = (static_cast<size_t>(k) * dims.y + j) * dims.x + i;
        const ptrdiff_t c = (k + 1) * sz + (j + 1) * sy + i + 1;
        for (int o = 0; o < kOctants; ++o) out[kOctants * n + o] = d[o * plane + c];
      }
}

}  // namespace imx
