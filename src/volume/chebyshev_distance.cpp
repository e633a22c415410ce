#include "volume/chebyshev_distance.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace imx {

void chebyshev_distance(std::span<const uint8_t> occupied, glm::ivec3 dims,
                        std::span<uint8_t> out) {
  // A one-cell border of 255 removes every bounds test from the passes.
  const ptrdiff_t px = dims.x + 2, py = dims.y + 2, pz = dims.z + 2;
  const ptrdiff_t sy = px, sz = px * py;
  std::vector<uint8_t> d(static_cast<size_t>(px * py * pz), 255);
  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i) {
        size_t n = (static_cast<size_t>(k) * dims.y + j) * dims.x + i;
        d[(k + 1) * sz + (j + 1) * sy + i + 1] = occupied[n] ? 0 : 255;
      }

  // The 13 neighbours that precede a cell in raster order (z, then y, then x).
  std::array<ptrdiff_t, 13> before{};
  int m = 0;
  for (int dz = -1; dz <= 0; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ptrdiff_t off = dz * sz + dy * sy + dx;
        if (off < 0) before[m++] = off;
      }

  auto relax = [&](ptrdiff_t c, int sign) {
    int best = d[c];
    for (ptrdiff_t off : before) best = std::min(best, d[c + sign * off] + 1);
    d[c] = static_cast<uint8_t>(std::min(best, 255));
  };
  for (int k = 1; k <= dims.z; ++k)
    for (int j = 1; j <= dims.y; ++j)
      for (int i = 1; i <= dims.x; ++i) relax(k * sz + j * sy + i, 1);
  for (int k = dims.z; k >= 1; --k)
    for (int j = dims.y; j >= 1; --j)
      for (int i = dims.x; i >= 1; --i) relax(k * sz + j * sy + i, -1);

  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i)
        out[(static_cast<size_t>(k) * dims.y + j) * dims.x + i] =
            d[(k + 1) * sz + (j + 1) * sy + i + 1];
}

}  // namespace imx
