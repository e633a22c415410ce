// Octant distance map: for every cell and each of the eight directions a ray can travel in, how
// far the empty space ahead of the cell reaches.
#pragma once
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

namespace imx {

// The octant of a direction: bit a set when it runs toward lower indices on axis a (an axis it
// does not move along counts as rising).
constexpr int kOctants = 8;

// out[8 n + o] = the Chebyshev distance from cell n to the nearest occupied cell q in octant o
// (q - n of the octant's sign, or 0, on every axis): 0 for an occupied cell, else the side k of
// the largest cube of unoccupied cells with n as its corner that extends k - 1 cells toward o.
// A ray leaving n toward o meets no occupied cell before it leaves that cube. Cells past the grid
// count as unoccupied; saturated at 255 (also the value when nothing lies ahead). Cells are
// x-fastest, dims.x * dims.y * dims.z of them. O(cells): one sweep per octant, each cell taking
// one more than the least of its seven neighbours ahead.
void octant_distance(std::span<const uint8_t> occupied, glm::ivec3 dims, std::span<uint8_t> out);

}  // namespace imx
