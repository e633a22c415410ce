// Chebyshev (chessboard) distance transform of a 3D grid of flags, in two raster passes.
#pragma once
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

namespace imx {

// out[n] = min over cells q with occupied[q] != 0 of max_i |p_i - q_i|, saturated at 255 (also
// the value everywhere when nothing is occupied). Cells are x-fastest, dims.x * dims.y * dims.z
// of them. Exact: see docs/volume_acceleration.md for why two 26-neighbour passes suffice.
void chebyshev_distance(std::span<const uint8_t> occupied, glm::ivec3 dims, std::span<uint8_t> out);

}  // namespace imx
